"""``python -m agents.benchmark``: runs ``agents.benchmark.cli`` (the ``dynnav-benchmark`` command)."""

from agents.benchmark.cli import main

if __name__ == "__main__":
    main()
