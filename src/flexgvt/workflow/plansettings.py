"""The project file's [plan] table (pre-test planning, `flexgvt plan project.toml`) as a settings
dataclass: each key's type, default, unit, limits and description defined once (the schema's
[plan] table is generated from it, docs/settings.md too)."""

from __future__ import annotations

from dataclasses import dataclass

from ..updating.settings import check_settings, setting


@dataclass(frozen=True)
class PlanSettings:
    """Pre-test planning (`flexgvt plan`): candidate suspensions (every station with every line
    rate and cord length), sensors by effective independence and driving points, on each deformed
    configuration."""

    configurations: tuple[str, ...] = setting((), "the project's configurations to plan on (default: all of them)")
    n_modes: int = setting(8, "elastic target modes per configuration (the lowest ones, inside band_hz)", ge=1, le=60)
    band_hz: tuple[float, float] | None = setting(None, "frequency band of the target modes [low, high] (default: "
                                                  "the n_modes lowest elastic modes)", unit="Hz", ge=0, size=2)
    stations: tuple[tuple[int, ...], ...] = setting((), "candidate suspension stations: each a list of the nodes "
                                                    "hung at once, e.g. [[110, 132], [101, 141]]")
    stiffness: tuple[float, ...] = setting((), "candidate line rates, each tried at every station", unit="N/m",
                                           gt=0)
    length: tuple[float, ...] = setting((), "candidate cord lengths: the anchor this far above each attachment "
                                        "(against gravity)", unit="m", gt=0)
    allowed_load: float | None = setting(None, "load a line may carry (default: no limit)", unit="N", gt=0)
    sensors: int = setting(12, "number of response sensors to place", ge=1)
    sensor_nodes: tuple[int, ...] = setting((), "candidate sensor nodes (default: every node)")
    directions: str = setting("XYZ", "sensor directions tried at each candidate node: letters of X, Y, Z (global "
                              "axes of the undeformed model, turning with the deformed structure)")
    exciters: int = setting(3, "driving points listed, best first", ge=1)
    exciter_nodes: tuple[int, ...] = setting((), "candidate driving-point nodes (default: the sensor candidates)")
    exciter_directions: str = setting("", "directions tried at each exciter node (default: directions)")
    energy_limit: float = setting(0.1, "an elastic mode with more than this share of its energy in the "
                                  "suspension is contaminated", gt=0, le=1)
    shift_limit_percent: float = setting(1.0, "an elastic mode the suspension moves by more than this from "
                                         "free-free is contaminated", gt=0)

    def __post_init__(self) -> None:
        object.__setattr__(self, "stations", tuple(tuple(int(n) for n in s) for s in self.stations))
        for key in ("configurations", "stiffness", "length", "sensor_nodes", "exciter_nodes"):
            object.__setattr__(self, key, tuple(getattr(self, key)))
        if self.band_hz is not None:
            object.__setattr__(self, "band_hz", tuple(self.band_hz))
        check_settings(self, "plan settings")
        for key in ("stiffness", "length"):
            for v in getattr(self, key):
                if not v > 0 or v == float("inf"):
                    raise ValueError(f"{key}: {v!r} must be finite and > 0")
        for key in ("directions", "exciter_directions"):
            bad = set(getattr(self, key).upper()) - set("XYZ")
            if bad or (key == "directions" and not self.directions):
                raise ValueError(f"{key}: '{getattr(self, key)}' must be letters of X, Y, Z (e.g. \"Z\" for "
                                 "out-of-plane sensors)")
        if self.band_hz is not None and not self.band_hz[0] < self.band_hz[1]:
            raise ValueError(f"band_hz: {list(self.band_hz)} must be [low, high] with low < high [Hz]")
        if any(len(s) == 0 for s in self.stations):
            raise ValueError("stations: a station lists at least one node")
