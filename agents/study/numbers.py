"""The study's published numbers, keyed by experiment (the config file's name in configs/).

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
    "moving_target_5_2": dict(success="100%", converge="~800", source="Sec. 6.1, Figs. 6.1-6.2"),
    "moving_obstacles_5_3": dict(success="93% (Sec. 6.1: over 90%)", converge="~2000",
                                 source="Fig. 6.3, Table 6.2 (distance)"),
    "motion_areas_5_4a": dict(success="-", converge="~2000", source="Fig. 6.4: learned"),
    "motion_areas_route_5_4b": dict(success="~94%", converge="~2000 (Fig. 6.9: ~2500)",
                                    source="Figs. 6.5, 6.9 (distance)"),
    "overlapping_areas_5_4c": dict(success="failed", converge="never", source="Fig. 6.6: reward stayed below 0"),
    "rewards_5_4b_distance_orientation": dict(success="~94%", converge="~2500", source="Fig. 6.9"),
    "rewards_5_4b_distance_orientation_always": dict(success="~94%", converge="~2500",
                                                     source="Fig. 6.9: best curves of the three"),
    "rewards_5_4b_potential": dict(success="~94%", converge="~2500", source="Fig. 6.9"),
    "rewards_5_3_distance_orientation": dict(success="-", converge="-", source="Fig. 6.8: as distance"),
    "rewards_5_3_distance_orientation_always": dict(success="94%", converge="-", source="Fig. 6.11, Table 6.2"),
    "distance_gamma_0_1_5_2": dict(success="-", converge="-", source="Fig. 6.7: lowest reward"),
    "distance_gamma_0_3_5_2": dict(success="-", converge="-", source="Fig. 6.7: higher loss than 0.2"),
    "potential_gamma_0_85_5_3": dict(success="88%", converge="-", source="Table 6.1; 150 test steps on average"),
    "potential_gamma_0_9_5_3": dict(success="96%", converge="-", source="Tables 6.1, 6.2"),
    "potential_gamma_0_95_5_3": dict(success="94%", converge="-", source="Table 6.1"),
    "potential_gamma_1_0_5_3": dict(success="65%", converge="-", source="Table 6.1: turns in place"),
    "camera_5_5a": dict(success="93%", converge="~1700", source="Sec. 6.3 Exp. 1, Fig. 6.15; 24 test steps"),
    "laser_pos_5_5b": dict(success="92%", converge="~1500", source="Table 6.3, Fig. 6.18"),
    "camera_pos_5_5b": dict(success="64%", converge="~1500", source="Table 6.3, Fig. 6.18"),
    "laser_camera_pos_5_5b": dict(success="96%", converge="~1900", source="Table 6.3, Figs. 6.17-6.18"),
    "frames_1_5_5c": dict(success="33%", converge="-", source="Table 6.4, Fig. 6.19"),
    "frames_2_5_5c": dict(success="41%", converge="-", source="Table 6.4, Fig. 6.19"),
    "frames_4_5_5c": dict(success="99%", converge="-", source="Table 6.4, Figs. 6.19, 6.22"),
}

# Runs made directly from the two original configs carry their ``name`` field, not the file's.
ALIASES = {"thesis_5_2": "moving_target_5_2", "thesis_5_3": "moving_obstacles_5_3"}

# Comparison figures after the study's: (file stem, title, [(experiment, label), ...]).
FIGURES = [
    ("preliminary", "Preliminary worlds (Figs. 6.1-6.6), reward distance", [
        ("moving_target_5_2", "5.2 moving targets"), ("moving_obstacles_5_3", "5.3 moving obstacles"),
        ("motion_areas_5_4a", "5.4a areas"), ("motion_areas_route_5_4b", "5.4b areas + route"),
        ("overlapping_areas_5_4c", "5.4c overlapping")]),
    ("fig6_7_distance_gamma", "Distance reward 1 - exp(g d1) on 5.2 (Fig. 6.7)", [
        ("distance_gamma_0_1_5_2", "g = 0.1"), ("moving_target_5_2", "g = 0.2"),
        ("distance_gamma_0_3_5_2", "g = 0.3")]),
    ("fig6_8_rewards_5_3", "Rewards on 5.3 (Fig. 6.8)", [
        ("moving_obstacles_5_3", "distance (4.3)"), ("rewards_5_3_distance_orientation", "distance + orientation (4.5)")]),
    ("fig6_9_rewards_5_4b", "Rewards on 5.4b (Fig. 6.9)", [
        ("motion_areas_route_5_4b", "distance (4.3)"),
        ("rewards_5_4b_distance_orientation", "orientation near-free (4.5)"),
        ("rewards_5_4b_distance_orientation_always", "orientation always (4.6)"),
        ("rewards_5_4b_potential", "potential (4.9)")]),
    ("fig6_10_potential_gamma", "Potential reward gamma on 5.3 (Fig. 6.10)", [
        ("potential_gamma_0_85_5_3", "gamma 0.85"), ("potential_gamma_0_9_5_3", "gamma 0.9"),
        ("potential_gamma_0_95_5_3", "gamma 0.95"), ("potential_gamma_1_0_5_3", "gamma 1.0")]),
    ("fig6_11_rewards_5_3", "Rewards on 5.3 (Fig. 6.11)", [
        ("moving_obstacles_5_3", "distance (4.3)"),
        ("rewards_5_3_distance_orientation_always", "orientation always (4.6)"),
        ("potential_gamma_0_9_5_3", "potential (4.9)")]),
    ("fig6_18_sensors_5_5b", "Sensors on 5.5b (Fig. 6.18)", [
        ("laser_pos_5_5b", "laser + positions"), ("camera_pos_5_5b", "camera + positions"),
        ("laser_camera_pos_5_5b", "laser + camera + positions")]),
    ("fig6_19_frames_5_5c", "Camera frames on 5.5c (Fig. 6.19)", [
        ("frames_1_5_5c", "single frame"), ("frames_2_5_5c", "2 frames"), ("frames_4_5_5c", "4 frames")]),
    # beyond the study (configs/beyond/)
    ("beyond_rare_colours", "Auto-encoder loss weighted by colour rarity (beyond the study)", [
        ("camera_5_5a", "5.5a camera, Eq. 4.10"), ("camera_5_5a_rare_colours", "5.5a camera, rare colours"),
        ("camera_pos_5_5b", "5.5b camera + pos, Eq. 4.10"),
        ("camera_pos_5_5b_rare_colours", "5.5b camera + pos, rare colours"),
        ("laser_camera_pos_5_5b", "5.5b laser + camera + pos, Eq. 4.10"),
        ("laser_camera_pos_5_5b_rare_colours", "5.5b laser + camera + pos, rare colours")]),
]
