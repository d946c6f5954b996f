"""The layout of a UFF file read from its bytes, without pyuff: where each dataset starts and ends,
which one a cut-off file ends inside, and a summary of what a file holds (`describe_uff`).

A dataset is delimited by two lines holding only '-1'; the line after the first gives its number
('58b' for the binary 58, whose ID line gives the count of ASCII lines and of binary bytes that follow).
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import FileFormatError

DIRECTIONS = {1: "+X", 2: "+Y", 3: "+Z", 4: "+RX", 5: "+RY", 6: "+RZ",
              -1: "-X", -2: "-Y", -3: "-Z", -4: "-RX", -5: "-RY", -6: "-RZ", 0: "scalar"}
FUNCTION_TYPES = {0: "general", 1: "time response", 2: "auto spectrum", 3: "cross spectrum", 4: "FRF",
                  5: "transmissibility", 6: "coherence", 7: "auto correlation", 8: "cross correlation",
                  9: "power spectral density", 10: "energy spectral density", 11: "probability density",
                  12: "spectrum", 13: "cumulative frequency distribution", 14: "peaks valley", 15: "stress/cycles",
                  16: "strain/cycles", 17: "orbit", 18: "mode indicator function", 19: "force pattern",
                  20: "partial power", 21: "partial coherence", 22: "eigenvalue", 23: "eigenvector",
                  24: "shock response spectrum", 25: "finite impulse response filter",
                  26: "multiple coherence", 27: "order function"}
NAMES = {15: "nodes", 18: "coordinate systems", 55: "modes", 58: "functions", 82: "trace lines", 151: "header",
         164: "units", 2400: "model header", 2411: "nodes", 2412: "elements", 2414: "analysis results (modes)",
         2420: "coordinate systems", 1858: "function qualifiers", 2429: "permanent groups", 2467: "groups"}


def get_field(s: dict, key: str, where: str):
    """A field of a pyuff dataset dict; missing -> FileFormatError naming the dataset and field."""
    if key not in s:
        raise FileFormatError(f"{where}: no field '{key}' (the dataset is incomplete or of a variant flexgvt "
                              "does not read); re-export the file")
    return s[key]


def as_int(value, where: str, what: str) -> int:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise FileFormatError(f"{where}: {what} {value!r} is not a number") from None
    if not np.isfinite(v) or v != int(v) or abs(v) > 2**31:
        raise FileFormatError(f"{where}: {what} {value!r} is not an integer id/code")
    return int(v)


def as_ids(values, where: str, what: str = "node ids") -> np.ndarray:
    try:
        a = np.atleast_1d(np.asarray(values, float))
    except (TypeError, ValueError):
        raise FileFormatError(f"{where}: {what} are not numbers") from None
    if a.ndim != 1 or not np.all(np.isfinite(a)) or np.any(a != np.round(a)) or np.any(np.abs(a) > 2**31):
        raise FileFormatError(f"{where}: {what} must be integers")
    return a.astype(np.int64)


def as_column(values, where: str, what: str, n: int | None = None, dtype=float) -> np.ndarray:
    try:
        a = np.atleast_1d(np.asarray(values, dtype))
    except (TypeError, ValueError):
        raise FileFormatError(f"{where}: {what} are not numbers (a field shifted or cut?)") from None
    if a.ndim != 1 or (n is not None and len(a) != n):
        raise FileFormatError(f"{where}: {len(a)} values of {what} for {n} nodes (a line is missing or a node "
                              "count changed); re-export the file")
    return a



@dataclass(frozen=True)
class Block:
    """One dataset in the file: its number ('58b' read as 58, binary=True), its first and last lines
    (1-based, the delimiters included; last None when the file ends inside it)."""

    number: int
    first_line: int
    last_line: int | None
    binary: bool = False


def _is_delimiter(line: bytes) -> bool:
    return line.strip() == b"-1"


def scan(data: bytes) -> list[Block]:
    """The datasets of a UFF file's bytes, in order; the last has last_line None when the file is cut."""
    blocks: list[Block] = []
    pos, line_no, n = 0, 0, len(data)

    def next_line(p):
        end = data.find(b"\n", p)
        end = n if end < 0 else end + 1
        return data[p:end], end

    opened = 0  # a delimiter already read that opens the next dataset (after a binary 58b, see below)
    while pos < n:
        if opened:
            start, opened = opened, 0
        else:
            line, pos = next_line(pos)
            line_no += 1
            if not _is_delimiter(line):
                continue  # text between datasets is ignored, as the writers of UFF do
            start = line_no
        if pos >= n:
            blocks.append(Block(-1, start, None))
            break
        head, pos = next_line(pos)
        line_no += 1
        token = head.split()[0].decode("ascii", "replace") if head.split() else ""
        binary = token.lower().endswith("b")
        try:
            number = int(token[:-1] if binary else token)
        except ValueError:
            number = -1
        closed = False
        if binary:
            fields = head.split()
            try:
                n_ascii, n_bytes = int(fields[3]), int(fields[4])
            except (IndexError, ValueError):
                n_ascii, n_bytes = 0, 0
            for _ in range(n_ascii):
                if pos >= n:
                    break
                _, pos = next_line(pos)
                line_no += 1
            payload = data[pos:pos + n_bytes]
            line_no += payload.count(b"\n")
            if pos + n_bytes > n:
                blocks.append(Block(number, start, None, True))
                break
            pos += n_bytes
            # One delimiter after the binary record may close it and open the next dataset at once
            # (pyuff writes 58b so): a delimiter followed by a dataset number (not by a second
            # delimiter) both ends this dataset and starts the next.
            line, after = next_line(pos)
            if line in (b"\n", b"\r\n"):  # the end of the record's last line
                pos = after
                line, after = next_line(pos)
            if not _is_delimiter(line):
                # the byte count is wrong (pyuff writes half the bytes of complex doubles): the record
                # ends at the next delimiter, which may follow the binary data on the same line
                hit = data.find(b"    -1", pos)
                while hit >= 0 and hit + 6 < n and data[hit + 6:hit + 7] != b"\n" and data[hit + 6:hit + 8] != b"\r\n":
                    hit = data.find(b"    -1", hit + 1)
                if hit < 0:
                    blocks.append(Block(number, start, None, True))
                    break
                line_no += data.count(b"\n", pos, hit)
                pos = hit
                line, after = next_line(pos)
            if _is_delimiter(line):
                nxt, _ = next_line(after)
                pos = after
                line_no += 1
                closed = True
                if after < n and nxt.strip() and not _is_delimiter(nxt):
                    opened = line_no
                blocks.append(Block(number, start, line_no, True))
                continue
        while pos < n:
            line, pos = next_line(pos)
            line_no += 1
            if _is_delimiter(line):
                closed = True
                break
        blocks.append(Block(number, start, line_no if closed else None, binary))
    return blocks


def cut_message(path, blocks: list[Block]) -> str | None:
    """The message for a file that ends inside a dataset, else None."""
    if not blocks or blocks[-1].last_line is not None:
        return None
    cut = blocks[-1]
    complete = [b for b in blocks if b.last_line is not None]
    what = f"dataset {len(blocks)} (type {cut.number if cut.number >= 0 else '?'}, starting at line {cut.first_line})"
    if complete:
        last = complete[-1]
        before = (f"the last complete dataset is {len(complete)} (type {last.number}, lines {last.first_line}-"
                  f"{last.last_line})")
    else:
        before = "no dataset before it is complete"
    return (f"{path}: the file ends inside {what}: it was cut off (an interrupted transfer or export?); {before}. "
            f"Transfer or export the file again, or keep lines 1-{complete[-1].last_line if complete else 0} "
            "to read the complete datasets")


def read_blocks(path: Path) -> tuple[bytes, list[Block]]:
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise FileFormatError(f"{path}: cannot be read ({exc.strerror})") from None
    return data, scan(data)


@dataclass(frozen=True)
class UFFContents:
    """What a UFF file holds: dataset counts by number, the 58 functions as (function type name,
    response DOF name, reference DOF name, points), the points, coordinate systems, trace lines,
    elements and modes found, the units, and the cut-off message when the file is truncated."""

    path: str
    counts: dict
    functions: tuple = ()
    n_points: int = 0
    n_coordinate_systems: int = 0
    n_trace_lines: int = 0
    n_elements: int = 0
    n_modes: int = 0
    units: str = ""
    truncated: str | None = None
    notes: tuple = field(default_factory=tuple)

    def function_counts(self) -> Counter:
        return Counter(f[0] for f in self.functions)

    def summary(self) -> str:
        """One line: '1 time response (58 type 1): 0+X / 0; geometry: 36 points, ...'."""
        parts = []
        fc = self.function_counts()
        for kind, k in fc.items():
            dofs = [f"{r} / {ref}" for t, r, ref, _ in self.functions if t == kind]
            shown = ", ".join(dofs[:4]) + (f" and {len(dofs) - 4} more" if len(dofs) > 4 else "")
            parts.append(f"{k} {kind}{'s' if k > 1 else ''} (58 type {_type_code(kind)}): {shown}")
        parts += [f"{n} {what}" for n, what in ((self.n_points, "points"),
                                                 (self.n_coordinate_systems, "coordinate systems"),
                                                 (self.n_trace_lines, "trace lines"), (self.n_elements, "elements"),
                                                 (self.n_modes, "modes")) if n]
        if self.units:
            parts.append(f"units {self.units}")
        sets = ", ".join(f"{n} x{c}" if c > 1 else str(n) for n, c in self.counts.items())
        text = f"datasets {sets}" + (": " + "; ".join(parts) if parts else "")
        if self.truncated:
            text += " (the file is cut off)"
        return text

    def hint(self, wanted: str) -> str:
        """What to do with this file instead of ``wanted``."""
        fc = self.function_counts()
        if "time response" in fc and wanted != "time":
            return ("estimate FRFs from the time histories: flexgvt ema frf, or in Python "
                    "flexgvt.ema.estimate_frf_from_time(flexgvt.io.uff.read_time_histories(path))")
        if "FRF" in fc and wanted != "frf":
            return "it holds FRFs: read them with read_uff(path).frfs (flexgvt ema identify)"
        if self.n_modes and wanted != "modes":
            return "it holds modes: read them with read_uff(path).modes"
        if self.n_points:
            return ("it holds test geometry only: use it for the test points (read_uff(path).geometry) and give "
                    "the measurements in another file")
        return "export the data asked for from the test system"

    def __str__(self) -> str:
        return f"{self.path}: {self.summary()}"


def _type_code(kind: str) -> str:
    codes = {name: code for code, name in FUNCTION_TYPES.items()}
    return str(codes.get(kind, "?"))
