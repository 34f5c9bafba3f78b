"""Pretrained navigators: per numbered cell of the study, the Q-network (and auto-encoder) of
one seed of its best row, in ``pretrained/<cell>/`` as safetensors with its config and card.

    from agents.pretrained import load

    navigator = load("5.3")            # or pretrained:5.3 wherever a checkpoint is taken
    action = navigator.act(obs)

``python -m agents.pretrained list | export | train`` (``agents.pretrained.cli``); the files and
how a name finds them: ``agents.training.pretrained_files``.
"""

from agents.pretrained.navigator import Navigator, available, load

__all__ = ["Navigator", "available", "load"]
