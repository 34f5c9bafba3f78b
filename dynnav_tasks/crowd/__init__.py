"""Pedestrians: the motion models that move them (social force, ORCA), in plain numpy and Python.

``social_force.py`` (Helbing and Molnár 1995) and ``orca.py`` (van den Berg et al. 2011) each
give a crowd's new velocities from its positions, velocities, radii and goals, and from the
bodies it avoids that are not pedestrians (a robot it sees, the static boxes and walls).
"""
