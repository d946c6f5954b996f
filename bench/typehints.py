"""Exported functions and methods (a package's __all__) lacking type hints on a parameter or the return.

    python bench/typehints.py updating workflow suspension cases model
"""

import importlib
import inspect
import sys

pk = sys.argv[1:] or ["updating", "workflow", "suspension", "cases", "model"]
missing = []
total = 0
for name in pk:
    mod = importlib.import_module(f"flexgvt.{name}")
    for attr in getattr(mod, "__all__", []):
        obj = getattr(mod, attr)
        items = []
        if inspect.isfunction(obj):
            items.append((f"{name}.{attr}", obj))
        elif inspect.isclass(obj) and obj.__module__.startswith("flexgvt"):
            for m, f in vars(obj).items():
                if (inspect.isfunction(f) or isinstance(f, (classmethod, staticmethod))) and not m.startswith("_"):
                    items.append((f"{name}.{attr}.{m}", getattr(f, "__func__", f)))
        for label, f in items:
            total += 1
            sig = inspect.signature(f)
            bad = [p for p, v in sig.parameters.items() if p not in ("self", "cls") and v.annotation is inspect._empty
                   and v.kind not in (v.VAR_POSITIONAL, v.VAR_KEYWORD)]
            if sig.return_annotation is inspect._empty or bad:
                missing.append(f"{label}: {'return ' if sig.return_annotation is inspect._empty else ''}{bad}")
print(f"{len(missing)} of {total} lack hints")
print("\n".join(missing))
