"""The one place that knows ManiSkill 3.0.1's internals: the SAPIEN objects behind its structs.

ManiSkill wraps SAPIEN's objects in batched "structs" (``Actor``, ``Articulation``, ``Link``,
``ArticulationJoint``) that hold one object per parallel sub-scene in the private lists
``_objs`` and ``_bodies``, and offers no public accessor for them. A dynnav task runs one
environment on the CPU simulation, so each struct holds exactly one object, and the task
talks to it directly (numpy in, numpy out: no batched torch round trip on every step).

Every other module goes through these two functions; if a ManiSkill release renames those
lists, this file is the one to change.
"""

from __future__ import annotations


def sapien_object(struct):
    """The single SAPIEN object a ManiSkill struct manages in a one-environment scene.

    ``Articulation`` -> ``sapien.physx.PhysxArticulation``; ``Link`` ->
    ``PhysxArticulationLinkComponent``; ``ArticulationJoint`` -> ``PhysxArticulationJoint``;
    ``Actor`` -> its ``sapien.Entity``.
    """
    return _only(struct._objs, struct)


def physx_body(actor):
    """The PhysX rigid body component of a ManiSkill ``Actor`` in a one-environment scene
    (a ``PhysxRigidDynamicComponent`` for a kinematic or dynamic actor)."""
    return _only(actor._bodies, actor)


def _only(objects: list, struct):
    if len(objects) != 1:
        raise ValueError(f"{struct!r} manages {len(objects)} SAPIEN objects; dynnav tasks run one environment "
                         "per process (num_envs=1)")
    return objects[0]
