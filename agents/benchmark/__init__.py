"""``dynnav-benchmark``: one policy scored on a named suite of tasks, the same way every time.

    dynnav-benchmark --policy pretrained:procedural --suite procedural
    dynnav-benchmark --policy my_agent:act --suite study --out results/scorecards/mine.json
    dynnav-benchmark --policy ppo.zip --algo ppo --task DynNav-MovingTarget-v1 --options control_mode=diff_drive_vel

``suites.py`` fixes each suite's tasks, seeds and episode counts; ``policies.py`` turns a policy
spec (a pretrained name, a run directory, a Stable-Baselines3 ``.zip``, ``module:function``) into
something that acts; ``scoring.py`` plays the episodes on both cores and scores them;
``card.py`` writes the score card (JSON and Markdown) beside the planner's ceiling and the
go-to-target floor; ``leaderboard.py`` makes docs/leaderboard.md from committed score cards.
"""
