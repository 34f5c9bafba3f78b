"""Score two policies on the procedural suite with ``dynnav-benchmark``: a Stable-Baselines3 PPO
trained here for a few minutes, and a hand-written callable.

    python examples/benchmark_procedural.py [--steps 20000] [--episodes 10]

The PPO learns on the easy train worlds (the discrete drive, the task's default state) and is
saved to runs/examples/ppo-procedural.zip; the callable (``toward_target`` below: face the target,
then drive) needs no training. Both are scored on the same cells and seeds: each difficulty's
test and ood worlds, ``--episodes`` each (the suite's published count is 100). The score cards
go to runs/examples/.
"""

import argparse
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent


def toward_target(obs):
    """Turn until the target is ahead, then drive: the egocentric state's target part is its
    distance, then the sine and cosine of its bearing, after the 16 lasers."""
    sin_b, cos_b = float(obs[17]), float(obs[18])
    if cos_b > 0.97:
        return 0
    return 1 if sin_b > 0 else 2


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--steps", type=int, default=20_000, help="PPO's training steps")
    parser.add_argument("--episodes", type=int, default=10, help="episodes per cell")
    args = parser.parse_args()
    import stable_baselines3 as sb3
    import torch

    import dynnav_tasks
    from agents.benchmark.cli import main as benchmark

    torch.set_num_threads(1)
    out = Path("runs/examples")
    out.mkdir(parents=True, exist_ok=True)
    env = dynnav_tasks.NumpyWrapper(dynnav_tasks.make("DynNav-Procedural-v1", difficulty="easy", split="train"))
    model = sb3.PPO("MlpPolicy", env, seed=0, device="cpu", verbose=0)
    model.learn(args.steps, progress_bar=False)
    model.save(out / "ppo-procedural.zip")
    env.close()
    sys.path.insert(0, str(HERE))  # so that the benchmark's workers import this file as a module
    common = ["--suite", "procedural", "--episodes", str(args.episodes), "--no-progress"]
    benchmark(["--policy", str(out / "ppo-procedural.zip"), "--algo", "ppo", "--out", str(out / "ppo.json"), *common])
    benchmark(["--policy", "benchmark_procedural:toward_target", "--out", str(out / "toward-target.json"), *common])


if __name__ == "__main__":
    main()
