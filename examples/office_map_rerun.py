"""The procedural navigator in the shipped office floor, with moving boxes and pedestrians,
recorded to Rerun.

    python examples/office_map_rerun.py [--episodes 3] [--out runs/office.rrd] [--model procedural]

The navigator (``pretrained:procedural``, trained on generated worlds only) plays
``DynNav-Map-v1`` made with the options its own task had (``way=True``, four box slots, turns in
place), so it reads the office exactly as it read the generated worlds. Open the recording with
``rerun runs/office.rrd``.
"""

import argparse

import numpy as np

import dynnav_tasks
from agents.pretrained import load
from dynnav_tasks.viz.recording import Recorder

STATE_OPTIONS = ("way", "obstacle_k", "human_k", "turn_forward_step", "laser_rays")
"""the task options that shape what a navigator reads and how it drives"""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--model", default="procedural", help="a pretrained procedural navigator")
    parser.add_argument("--episodes", type=int, default=3)
    parser.add_argument("--out", default="runs/office.rrd", help="the Rerun recording (.rrd)")
    parser.add_argument("--moving-obstacles", type=int, default=3)
    parser.add_argument("--pedestrians", type=int, default=4)
    args = parser.parse_args()
    with load(args.model) as navigator:
        own = navigator.policy.config.env.task_kwargs
        options = {k: v for k, v in own.items() if k in STATE_OPTIONS}
        env = dynnav_tasks.NumpyWrapper(dynnav_tasks.make("DynNav-Map-v1", moving_obstacles=args.moving_obstacles,
                                                          pedestrians=args.pedestrians, **options))
        recorder = Recorder(args.out)
        try:
            for episode in range(args.episodes):
                obs, _ = env.reset(seed=episode)
                navigator.reset()
                recorder.start_episode(env, episode)
                done = False
                while not done:
                    q_values = navigator.q_values(obs)  # once per step: a memory would advance twice
                    action = int(np.argmax(q_values))
                    obs, reward, terminated, truncated, info = env.step(action)
                    recorder.log_step(env, action=action, reward=float(reward), q_values=q_values)
                    done = terminated or truncated
                print(f"episode {episode}: {recorder.end_episode(info)}")
        finally:
            recorder.close()
            env.close()
    print(f"recording: {args.out} (rerun {args.out})")


if __name__ == "__main__":
    main()
