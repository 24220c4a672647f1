# make        : set up .venv, regenerate equations, code and docs, run a demo scene
# make test   : set up .venv and run the tests (incl. the stale check and the PDF build)
# make bench  : kernel, step and contact-force benchmarks (bench/README.md); make report : work-precision report
VENV := .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed
DEMO ?= scenes/disc_in_bowl.toml

.PHONY: all setup tex regenerate docs demo test lint bench report soak clean

all: regenerate demo

$(STAMP): pyproject.toml
	test -x $(PY) || python3 -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e '.[dev]'
	touch $@

setup: $(STAMP)

# pdflatex from Debian's TeX Live when missing (root on CI; sudo elsewhere when available).
tex:
	@command -v pdflatex >/dev/null 2>&1 || { \
	  SUDO=$$( [ "$$(id -u)" = 0 ] || echo sudo ); \
	  $$SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq \
	    --no-install-recommends texlive-latex-base texlive-latex-recommended \
	    texlive-fonts-recommended lmodern >/dev/null; }

regenerate: setup tex
	$(VENV)/bin/regenerate-equations

docs: setup tex
	$(VENV)/bin/regenerate-equations

demo: setup
	$(VENV)/bin/simulate $(DEMO) --duration 2 --out out/demo --force

test: setup tex
	$(VENV)/bin/regenerate-equations --check
	$(VENV)/bin/pytest
	$(MAKE) --no-print-directory pdf-check

# The document must build: compile it into a scratch copy (the committed PDF is not touched).
pdf-check:
	@tmp=$$(mktemp -d) && cp docs/derivations.tex $$tmp/ && \
	  (cd $$tmp && pdflatex -interaction=nonstopmode -halt-on-error derivations.tex >/dev/null) && \
	  echo "derivations.tex builds: $$(pdfinfo $$tmp/derivations.pdf 2>/dev/null | grep Pages || echo ok)"; \
	  rc=$$?; rm -rf $$tmp; exit $$rc

lint: setup
	$(VENV)/bin/ruff check .
	$(VENV)/bin/ruff format --check .

bench: setup
	$(PY) -m bench.kernels
	$(PY) -m bench.steps
	$(PY) -m bench.lcp

report: setup
	$(PY) -m pip install --quiet -e '.[dev,peers]'
	$(PY) -m bench.report

soak: setup
	$(PY) -m bench.soak

clean:
	rm -rf out .pytest_cache .ruff_cache
