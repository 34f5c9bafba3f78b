"""The study's published numbers, keyed by experiment (the config file's name in configs/study/).

``success`` is the test success rate over 100 episodes as the study states it, ``converge`` the
training episodes it reports before the reward settled, ``source`` where it says so.

Where the study's numbers come from (thesis Sec. 6.1-6.2):
* Table 6.2 (distance 93%, orientation 94%, potential 96%) follows the sentence "we make a
  comparison among these three reward functions in the environment from Figure 5.3" and the
  potential entry equals Table 6.1's gamma 0.9 on 5.3, so it is keyed to the 5.3 experiments.
  On 5.4b (Fig. 6.9) the study gives one number for all three functions: "around 94%".
* The distance-reward sweep (Fig. 6.7) and the 5.4a / 5.4c worlds have curves only.
"""

from __future__ import annotations

THESIS = {
    "5.2": dict(success="100%", converge="~800", source="Sec. 6.1, Figs. 6.1-6.2"),
    "5.3": dict(success="93% (Sec. 6.1: over 90%)", converge="~2000", source="Fig. 6.3, Table 6.2 (distance)"),
    "5.4a": dict(success="-", converge="~2000", source="Fig. 6.4: learned"),
    "5.4b": dict(success="~94%", converge="~2000 (Fig. 6.9: ~2500)", source="Figs. 6.5, 6.9 (distance)"),
    "5.4c": dict(success="failed", converge="never", source="Fig. 6.6: reward stayed below 0"),
    "5.4b-orientation": dict(success="~94%", converge="~2500", source="Fig. 6.9"),
    "5.4b-orientation-always": dict(success="~94%", converge="~2500", source="Fig. 6.9: best curves of the three"),
    "5.4b-potential": dict(success="~94%", converge="~2500", source="Fig. 6.9"),
    "5.3-orientation": dict(success="-", converge="-", source="Fig. 6.8: as distance"),
    "5.3-orientation-always": dict(success="94%", converge="-", source="Fig. 6.11, Table 6.2"),
    "5.2-g0.1": dict(success="-", converge="-", source="Fig. 6.7: lowest reward"),
    "5.2-g0.3": dict(success="-", converge="-", source="Fig. 6.7: higher loss than 0.2"),
    "5.3-potential-0.85": dict(success="88%", converge="-", source="Table 6.1; 150 test steps on average"),
    "5.3-potential-0.9": dict(success="96%", converge="-", source="Tables 6.1, 6.2"),
    "5.3-potential-0.95": dict(success="94%", converge="-", source="Table 6.1"),
    "5.3-potential-1.0": dict(success="65%", converge="-", source="Table 6.1: turns in place"),
    "5.5a-camera": dict(success="93%", converge="~1700", source="Sec. 6.3 Exp. 1, Fig. 6.15; 24 test steps"),
    "5.5b-laser-pos": dict(success="92%", converge="~1500", source="Table 6.3, Fig. 6.18"),
    "5.5b-camera-pos": dict(success="64%", converge="~1500", source="Table 6.3, Fig. 6.18"),
    "5.5b-laser-camera-pos": dict(success="96%", converge="~1900", source="Table 6.3, Figs. 6.17-6.18"),
    "5.5c-frames-1": dict(success="33%", converge="-", source="Table 6.4, Fig. 6.19"),
    "5.5c-frames-2": dict(success="41%", converge="-", source="Table 6.4, Fig. 6.19"),
    "5.5c-frames-4": dict(success="99%", converge="-", source="Table 6.4, Figs. 6.19, 6.22"),
}

# Comparison figures after the study's: (file stem, title, [(experiment, label), ...]).
FIGURES = [
    ("preliminary", "Preliminary worlds (Figs. 6.1-6.6), reward distance", [
        ("5.2", "5.2 moving targets"), ("5.3", "5.3 moving obstacles"),
        ("5.4a", "5.4a areas"), ("5.4b", "5.4b areas + route"),
        ("5.4c", "5.4c overlapping")]),
    ("fig6_7_distance_gamma", "Distance reward 1 - exp(g d1) on 5.2 (Fig. 6.7)", [
        ("5.2-g0.1", "g = 0.1"), ("5.2", "g = 0.2"),
        ("5.2-g0.3", "g = 0.3")]),
    ("fig6_8_rewards_5_3", "Rewards on 5.3 (Fig. 6.8)", [
        ("5.3", "distance (4.3)"), ("5.3-orientation", "distance + orientation (4.5)")]),
    ("fig6_9_rewards_5_4b", "Rewards on 5.4b (Fig. 6.9)", [
        ("5.4b", "distance (4.3)"),
        ("5.4b-orientation", "orientation near-free (4.5)"),
        ("5.4b-orientation-always", "orientation always (4.6)"),
        ("5.4b-potential", "potential (4.9)")]),
    ("fig6_10_potential_gamma", "Potential reward gamma on 5.3 (Fig. 6.10)", [
        ("5.3-potential-0.85", "gamma 0.85"), ("5.3-potential-0.9", "gamma 0.9"),
        ("5.3-potential-0.95", "gamma 0.95"), ("5.3-potential-1.0", "gamma 1.0")]),
    ("fig6_11_rewards_5_3", "Rewards on 5.3 (Fig. 6.11)", [
        ("5.3", "distance (4.3)"),
        ("5.3-orientation-always", "orientation always (4.6)"),
        ("5.3-potential-0.9", "potential (4.9)")]),
    ("fig6_18_sensors_5_5b", "Sensors on 5.5b (Fig. 6.18)", [
        ("5.5b-laser-pos", "laser + positions"), ("5.5b-camera-pos", "camera + positions"),
        ("5.5b-laser-camera-pos", "laser + camera + positions")]),
    ("fig6_19_frames_5_5c", "Camera frames on 5.5c (Fig. 6.19)", [
        ("5.5c-frames-1", "single frame"), ("5.5c-frames-2", "2 frames"), ("5.5c-frames-4", "4 frames")]),
    # beyond the study
    ("beyond_rare_colours", "Auto-encoder loss weighted by colour rarity (beyond the study)", [
        ("5.5a-camera", "5.5a camera, Eq. 4.10"), ("5.5a-camera-rare-colours", "5.5a camera, rare colours"),
        ("5.5b-camera-pos", "5.5b camera + pos, Eq. 4.10"),
        ("5.5b-camera-pos-rare-colours", "5.5b camera + pos, rare colours"),
        ("5.5b-laser-camera-pos", "5.5b laser + camera + pos, Eq. 4.10"),
        ("5.5b-laser-camera-pos-rare-colours", "5.5b laser + camera + pos, rare colours")]),
]
