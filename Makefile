# dynnav: `make demo` runs the main job, `make test` runs the tests. Both create or refresh
# .venv first (scripts/setup.sh: CPU torch, the project, and a Vulkan driver if missing).
VENV ?= .venv
PY := $(VENV)/bin/python
TASK ?= DynNav-MovingTarget-v1

.PHONY: setup demo test bench pictures docs clean

setup:
	@bash scripts/setup.sh

demo: setup
	$(PY) -m agents.dqn --config configs/demo.yaml --task $(TASK)

test: setup
	$(PY) -m pytest -q tests

bench: setup
	$(PY) benchmarks/env_throughput.py

pictures: setup
	$(PY) -m dynnav_tasks.viz.pictures

docs: setup
	NO_MKDOCS_2_WARNING=1 $(VENV)/bin/mkdocs build --strict

clean:
	rm -rf $(VENV) .pytest_cache
