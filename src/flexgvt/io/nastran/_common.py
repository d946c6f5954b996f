"""Shared pieces of the Nastran bulk data reader and writer: units, the unsupported-cards error, eigen methods."""

from __future__ import annotations

from dataclasses import dataclass

from ...errors import FileFormatError, ModelError


class UnsupportedCardsError(FileFormatError):
    """The deck holds cards (or card features) flexgvt cannot represent; ``unsupported`` maps card -> ids."""

    def __init__(self, message: str, unsupported: dict[str, list] | None = None) -> None:
        super().__init__(message)
        self.unsupported = dict(unsupported or {})


@dataclass(frozen=True)
class Units:
    """A consistent Nastran unit system, given by its length and force units in SI (time: seconds).

    Mass is then force * s^2 / length (after PARAM,WTMASS), e.g. tonne for mm-N-s.
    """

    name: str
    length: float  # m per deck length unit
    force: float  # N per deck force unit

    @property
    def mass(self) -> float:  # kg per deck mass unit
        return self.force / self.length

    @property
    def density(self) -> float:
        return self.mass / self.length**3

    @property
    def stress(self) -> float:
        return self.force / self.length**2

    @property
    def inertia(self) -> float:  # kg m^2 per deck unit
        return self.mass * self.length**2

    @property
    def moment(self) -> float:  # N m per deck unit (also rotational stiffness per rad)
        return self.force * self.length


UNIT_SYSTEMS = {
    "SI": Units("SI", 1.0, 1.0),
    "mm-N-t-s": Units("mm-N-t-s", 1e-3, 1.0),
    "in-lbf-s": Units("in-lbf-s", 0.0254, 4.4482216152605),
}


def get_units(units: str | Units) -> Units:
    if isinstance(units, Units):
        return units
    try:
        return UNIT_SYSTEMS[units]
    except KeyError:
        raise ModelError(f"units={units!r} is not known; use one of {sorted(UNIT_SYSTEMS)} or a Units(name, length, "
                         "force) giving the deck's length and force units in m and N") from None


@dataclass(frozen=True)
class EigenMethod:
    """A subcase's real eigenvalue method (EIGRL, or EIGR with its METHOD).

    nd: number of modes (None: all in the window); f1, f2: frequency window [Hz] (None: open);
    norm: 'MASS' (phi^T M phi = 1), 'MAX' (largest component 1) or 'POINT' (component
    ``point`` = (grid, component 1-6) equal to 1). For EIGR with GIV/HOU/MGIV/MHOU, Nastran
    uses the window only when ND is blank; ``window_with_nd`` says whether both apply.
    """

    card: str
    sid: int
    method: str = "LAN"
    nd: int | None = None
    f1: float | None = None
    f2: float | None = None
    norm: str = "MASS"
    point: tuple[int, int] | None = None
    window_with_nd: bool = True
