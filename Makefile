# Two entry points on a fresh machine with Python 3.11: `make demo` and `make test`.
PYTHON ?= python3
VENV ?= .venv
BIN := $(VENV)/bin

.PHONY: demo test bench venv clean

$(BIN)/flexgvt: pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/pip install -q --upgrade pip
	$(BIN)/pip install -q -e '.[dev,mcmc]'
	touch $(BIN)/flexgvt

venv: $(BIN)/flexgvt

demo: venv
	MPLBACKEND=Agg $(BIN)/flexgvt demo --out demo-output

test: venv
	MPLBACKEND=Agg $(BIN)/python -m pytest -q -n 2

bench: venv
	MPLBACKEND=Agg $(BIN)/python bench/bench_solver.py --spread 8

clean:
	rm -rf $(VENV) demo-output .pytest_cache
