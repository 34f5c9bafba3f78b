"""``python -m agents.imitation``: behaviour cloning on the full-state planner's episodes, then DAgger.

    python -m agents.imitation --config configs/imitation/generalist.yaml
    python -m agents.imitation --config configs/imitation/generalist.yaml --seed 2 --rounds 6
    python -m agents.imitation --resume runs/imitation/<run>          # continue after the last finished round

Flags are ``ImitationConfig``'s fields (``--help`` lists them); a ``--config`` YAML gives them
first and the flags override it. Bad input ends with a one-line error before any file is written.
"""

from __future__ import annotations

import sys

import tyro

from agents.files import DiskFullError
from agents.imitation.config import ImitationConfig, load_yaml
from agents.imitation.dagger import saved_settings, train


def parse_args(argv: list[str]) -> ImitationConfig:
    """Flags over the ``--config`` file's settings (or, with ``--resume``, the run's own) over the defaults."""
    values = {}
    resume = next((argv[i + 1] for i, a in enumerate(argv[:-1]) if a == "--resume"), None) or next(
        (a.split("=", 1)[1] for a in argv if a.startswith("--resume=")), None)
    if resume is not None:
        values = saved_settings(resume)
    for i, arg in enumerate(argv):
        if arg == "--config" and i + 1 < len(argv):
            values = load_yaml(argv[i + 1])
            argv = argv[:i] + argv[i + 2:]
            break
        if arg.startswith("--config="):
            values = load_yaml(arg.split("=", 1)[1])
            argv = argv[:i] + argv[i + 1:]
            break
    return tyro.cli(ImitationConfig, args=argv, default=ImitationConfig(**values), description=ImitationConfig.__doc__)


def main(argv: list[str] | None = None) -> None:
    """Parse, train, print where the run is."""
    try:
        cfg = parse_args(list(sys.argv[1:] if argv is None else argv))
        run_dir = train(cfg)
    except (ValueError, DiskFullError) as err:
        raise SystemExit(f"error: {err}")
    print(f"\nrun directory: {run_dir}\n  test it: python -m agents.dqn --eval --checkpoint {run_dir}")


if __name__ == "__main__":
    main()
