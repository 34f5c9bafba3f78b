"""agents: DQN and Double DQN for dynnav tasks and any gymnasium env with discrete actions.

    python -m agents.dqn --config configs/study/5.2.yaml     # train (then test)
    python -m agents.dqn --eval --checkpoint runs/<run>              # test phase only
"""
