# make        : set up .venv, regenerate equations, code and docs, run a demo scene
# make test   : set up .venv and run the tests (incl. the stale check and the PDF build)
# make bench  : kernel, contact-finding, contact-force, step, target and ensemble benchmarks (bench/README.md)
# make report : work-precision report against pymunk and Box2D (docs/report/)
# make mutate : mutation testing (bench/mutants.py; ~35 min, not part of make test)
VENV := .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed
# the tests run in one process per core (pytest-xdist; whole files per process: their fixtures
# are built once)
TEST_WORKERS ?= auto
DEMO ?= scenes/disc_in_bowl.toml

.PHONY: all setup tex regenerate docs demo test pdf-check lint bench report soak mutate clean

all: regenerate demo

$(STAMP): pyproject.toml
	test -x $(PY) || python3 -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e '.[dev]'
	touch $@

setup: $(STAMP)

# pdflatex from Debian's TeX Live when missing: as root (CI) it is installed and a failure stops
# the job; elsewhere with passwordless sudo; otherwise one notice and the job goes on without the
# PDF (regenerate-equations skips it, pdf-check says it is skipped).
PDFLATEX ?= pdflatex
TEX_PACKAGES := texlive-latex-base texlive-latex-recommended texlive-fonts-recommended lmodern
tex:
	@command -v $(PDFLATEX) >/dev/null 2>&1 || { \
	  if [ "$$(id -u)" = 0 ]; then SUDO=; \
	  elif command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then SUDO="sudo -n"; \
	  else echo "make: pdflatex not found and not root (no passwordless sudo): going on without TeX; the PDF is skipped (install: apt-get install $(TEX_PACKAGES))"; exit 0; fi; \
	  $$SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq \
	    --no-install-recommends $(TEX_PACKAGES) >/dev/null; }

regenerate: setup tex
	$(VENV)/bin/regenerate-equations

docs: setup tex
	$(VENV)/bin/regenerate-equations

demo: setup
	$(VENV)/bin/simulate $(DEMO) --duration 2 --out out/demo --force

# the stale check of generated/ and docs/ is a test (tests/derive/test_regenerate.py), run beside
# the others: as a step of its own before them it kept one core busy for ~40 s
test: setup tex
	$(VENV)/bin/pytest -n $(TEST_WORKERS) --dist loadfile
	$(MAKE) --no-print-directory pdf-check

# The document must build: compile it into a scratch copy (the committed PDF is not touched).
# Without pdflatex (a non-root machine where `make tex` could not install it) it says so and
# passes; CI runs as root, where `make tex` has installed it.
pdf-check:
	@if ! command -v $(PDFLATEX) >/dev/null 2>&1; then \
	  echo "make: pdflatex not found: the PDF build check is skipped"; exit 0; fi; \
	  tmp=$$(mktemp -d) && cp docs/derivations.tex $$tmp/ && \
	  (cd $$tmp && $(PDFLATEX) -interaction=nonstopmode -halt-on-error derivations.tex >/dev/null) && \
	  echo "derivations.tex builds: $$(pdfinfo $$tmp/derivations.pdf 2>/dev/null | grep Pages || echo ok)"; \
	  rc=$$?; rm -rf $$tmp; exit $$rc

lint: setup
	$(VENV)/bin/ruff check .
	$(VENV)/bin/ruff format --check .

bench: setup
	$(PY) -m pip install --quiet -e '.[dev,peers]'
	$(PY) -m bench.kernels
	$(PY) -m bench.collide
	$(PY) -m bench.lcp
	$(PY) -m bench.steps
	$(PY) -m bench.profile_step
	$(PY) -m bench.targets
	$(PY) -m bench.ensemble

report: setup
	$(PY) -m pip install --quiet -e '.[dev,peers]'
	$(PY) -m bench.report

soak: setup
	$(PY) -m bench.soak

# Each mutant of bench/mutants.py against the tests that should catch it, in a scratch copy.
mutate: setup
	$(PY) -m bench.mutate

clean:
	rm -rf out .pytest_cache .ruff_cache
