"""Teacher-student learning: a sensor-only student imitates the full-state planner.

The planner (``dynnav_tasks.baselines.state_planner``) sees every obstacle's motion; the
student reads what the robot reads (the egocentric state). ``python -m agents.imitation``
clones the planner's episodes, then runs DAgger (``dagger.py``). Rooms:

* ``rollouts.py``: one episode with the teacher's label in every state;
* ``collector.py``: such episodes on several processes (labels cost tens of milliseconds);
* ``demonstrations.py``: the aggregated data and its file; ``offline_dataset.py``: the same as a
  Minari data set;
* ``fit.py``: the supervised fit; ``config.py``: the settings; ``dagger.py``: the loop.

The student is a DQN Q-network built from a training config, so ``agents.dqn`` tests it and
fine-tunes it like any run of its own.
"""
