"""Rebuild a deck from the echo in a Nastran .f06, and read its first REAL EIGENVALUES table.

Used once to make the test decks whose bulk data exists only as the f06's echo (see ORIGIN.md):
``python f06_echo.py run.f06 deck.bdf`` writes the executive control, the case control echo and the
sorted bulk data echo, each card line exactly as printed (column 30 on), page headers and line
counts removed; ``python f06_echo.py run.f06`` prints the cycles of the first eigenvalue table.
"""

import re
import sys

_CASE = re.compile(r"^ {10,}\d+ {6}")
_BULK = re.compile(r"^ +\d+- ")


def deck_from_echo(lines: list[str]) -> list[str]:
    out: list[str] = []
    mode = "exec"
    for line in lines:
        if "C A S E    C O N T R O L" in line:
            mode = "case"
        elif mode == "exec" and line.startswith("     ") and line.strip():
            out.append(line[5:].rstrip())
        elif mode == "case" and _CASE.match(line):
            out.append(line[25:].rstrip())
            mode = "bulk" if out[-1].strip().upper().startswith("BEGIN BULK") else mode
        elif mode == "bulk" and _BULK.match(line):
            out.append(line[30:].rstrip())
        elif mode == "bulk" and line[30:].strip() == "ENDDATA":
            out.append("ENDDATA")
            break
    return out


def first_eigenvalue_cycles(lines: list[str]) -> list[float]:
    start = next(i for i, line in enumerate(lines) if "R E A L   E I G E N V A L U E S" in line)
    cycles = []
    for line in lines[start + 3:]:
        parts = line.split()
        if len(parts) != 7 or not parts[0].isdigit():
            break
        cycles.append(float(parts[4]))
    return cycles


if __name__ == "__main__":
    text = open(sys.argv[1], errors="replace").read().splitlines()
    if len(sys.argv) > 2:
        open(sys.argv[2], "w").write("\n".join(deck_from_echo(text)) + "\n")
    else:
        print(first_eigenvalue_cycles(text))
