# NavVerse: `make` sets up, builds the default scenes and the default dataset; `make test` runs the suite.
SHELL := /bin/bash
PYTHON ?= python3
VENV ?= .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.navverse-setup
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
NAVVERSE := $(BIN)/navverse
DATASET ?= episodes/navverse-mini
SPLIT ?= eval
OUT ?= eval-out

.PHONY: all setup scenes full-scenes episodes eval bench status lint test docs clean help

all: setup scenes episodes  ## set up, then build the default scenes and dataset

help:  ## list the targets
	@grep -E '^[a-z-]+:.*## ' $(MAKEFILE_LIST) | sed -E 's/:.*## /\t/'

setup: $(STAMP)  ## system packages, virtual environment, editable install (runs once)

$(STAMP): pyproject.toml setup.py scripts/system-deps.sh
	./scripts/system-deps.sh
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install -q --upgrade pip
	$(BIN)/python -m pip install -q -e '.[dev,dem]'
	touch $(STAMP)

scenes: $(STAMP)  ## build every scene recipe in recipes/scenes
	$(NAVVERSE) build scenes --jobs $(JOBS)

full-scenes: $(STAMP)  ## the 200 scenes of the published navverse-full, checked against its scene hashes (~1 CPU-hour)
	$(NAVVERSE) build navverse-full-scenes --jobs $(JOBS)

episodes: $(STAMP)  ## build the dataset recipes in recipes/datasets (navverse-mini; manual ones by name)
	$(NAVVERSE) build datasets --jobs $(JOBS)

eval: $(STAMP)  ## score a submission: make eval SUBMISSION=file.jsonl [DATASET=...] [SPLIT=eval]
	@test -n "$(SUBMISSION)" || { echo "usage: make eval SUBMISSION=path/to/submission.jsonl [DATASET=$(DATASET)] [SPLIT=$(SPLIT)]"; exit 1; }
	$(NAVVERSE) eval --dataset $(DATASET) --submission $(SUBMISSION) --split $(SPLIT) --out $(OUT)

bench: $(STAMP)  ## run every benchmark in bench/ (prints ratios against peers; _*.py are helpers)
	@set -e; found=0; for b in bench/[!_]*.py; do [ -e "$$b" ] || continue; found=1; echo "== $$b"; $(BIN)/python $$b; done; \
	[ $$found = 1 ] || echo "bench/ has no benchmark yet"

status: $(STAMP)  ## fresh / stale / missing per target
	$(NAVVERSE) status

lint: $(STAMP)  ## ruff, then the layer contracts of pyproject.toml (import-linter)
	$(BIN)/ruff check .
	$(BIN)/ruff format --check .
	$(BIN)/lint-imports

test: $(STAMP)  ## the whole test suite
	$(BIN)/python -m pytest -n 2 -q

docs: $(STAMP)  ## the documentation site: mkdocs build --strict into site/ (generated stage and metric pages)
	NO_MKDOCS_2_WARNING=1 $(BIN)/mkdocs build --strict --site-dir site

clean:  ## remove build outputs (data/built), keeping the environment
	$(NAVVERSE) clean --all 2>/dev/null || rm -rf data/built/*
