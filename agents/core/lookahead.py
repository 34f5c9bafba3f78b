"""A Q-network that looks one step ahead: each action scored by the value of the state it leads to.

CrowdNav's learned navigators (CADRL, LSTM-RL, SARL: Chen et al. 2017, 2019) choose an action by a
one-step look-ahead: they move the robot by each action, move every human on at its current
velocity, and take the action whose next state a value network rates best. ``LookaheadQNetwork``
builds that look-ahead into a Q-network, so the bundled (Double) DQN trains it, tests it and ships
it unchanged: Q(s, a) = V(s + a), V of the *afterstate* s + a, the egocentric state moved one control
step on:

* the robot by the action: the discrete drive's advance and turn (``DriveConfig``: 0.15 m ahead,
  or a turn of pi/8 advancing ``turn_forward_step``, driven as an arc);
* each pedestrian by its own last step (constant velocity): its relative velocity plus the robot's
  odometry (the task's ``odometry=True``) is its step in the robot's frame;
* the target: fixed in the world;
* the laser ring: each reading's hit point seen from the new pose, the ring turned by the nearest
  whole number of rays (a pi/8 turn of the 16-ray ring: exactly one).

V reads the afterstate as SARL does (Chen et al. 2019): each pedestrian (position, velocity,
radius, its distance and the distance between the bodies' edges) beside the robot's part (the
target's distance and bearing, the move that led there) through one shared MLP; an attention
score per pedestrian from its features and the crowd's mean; the weighted sum, the robot's part,
the laser ring and the smallest edge distance through an MLP (``hidden_sizes``) to one value.
Empty slots (radius 0) get no weight. The network reads the scaled state the DQN feeds it and
undoes the scaling first (``offset``, ``scale``: ``agents.core.obs_scaling.ObsScaler``'s).
"""

from __future__ import annotations

import math
from typing import Sequence

import torch
from torch import nn

HUMAN_SLOT = 5
"""values per pedestrian slot: x, y, vx, vy, radius"""
EMBED = 64
"""width of each pedestrian's features"""
POSITION_SCALE, STEP_SCALE = 4.0, 0.15
"""m and m per step: what positions and steps are divided by before the MLPs"""


def _mlp(sizes: Sequence[int], last_relu: bool = True) -> nn.Sequential:
    layers: list[nn.Module] = []
    for i, (fan_in, fan_out) in enumerate(zip(sizes[:-1], sizes[1:])):
        layers.append(nn.Linear(fan_in, fan_out))
        if last_relu or i < len(sizes) - 2:
            layers.append(nn.ReLU())
    return nn.Sequential(*layers)


def arc(advance: torch.Tensor, turn: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
    """The displacement (ahead, left) of driving ``advance`` m along an arc that turns ``turn`` rad."""
    small = turn.abs() < 1e-6
    safe = torch.where(small, torch.ones_like(turn), turn)
    ahead = torch.where(small, advance, advance * torch.sin(safe) / safe)
    left = torch.where(small, torch.zeros_like(advance), advance * (1 - torch.cos(safe)) / safe)
    return ahead, left


class LookaheadQNetwork(nn.Module):
    """Q(s, a) = V(afterstate(s, a)) on the egocentric state ``lasers | target | odometry | humans``.

    ``moves``: (advance m, turn rad) of each action; ``laser_angles``: each ray's direction (rad, a
    full ring); ``laser_range``: a free ray's reading; ``robot_radius``: the circle round the robot's
    footprint (m); ``offset``, ``scale``: the DQN's input scaling (raw = scaled / scale + offset)."""

    def __init__(self, moves: Sequence[tuple[float, float]], laser_angles: Sequence[float], laser_range: float,
                 robot_radius: float, human_k: int, hidden_sizes: Sequence[int], offset: Sequence[float],
                 scale: Sequence[float]):
        super().__init__()
        self.lasers, self.human_k = len(laser_angles), int(human_k)
        width = self.lasers + 6 + HUMAN_SLOT * self.human_k
        if len(offset) != width or len(scale) != width:
            raise ValueError(f"the look-ahead reads {width} values (lasers, target, odometry, {human_k} pedestrians); "
                             f"the scaling has {len(offset)}")
        self.register_buffer("moves", torch.tensor(moves, dtype=torch.float32))
        self.register_buffer("angles", torch.tensor(laser_angles, dtype=torch.float32))
        self.register_buffer("offset", torch.tensor(offset, dtype=torch.float32))
        self.register_buffer("scale", torch.tensor(scale, dtype=torch.float32))
        self.laser_range, self.robot_radius = float(laser_range), float(robot_radius)
        spacing = 2 * math.pi / self.lasers
        self.shifts = [int(round(turn / spacing)) for _, turn in moves]
        """rays the ring turns by for each action"""
        robot = 6  # target distance, sin, cos; the move: ahead, left, turn
        self.each = _mlp([robot + 7, 128, EMBED])
        self.attention = _mlp([2 * EMBED, 64, 1], last_relu=False)
        self.laser_net = _mlp([self.lasers, 64])
        self.value = _mlp([robot + 64 + EMBED + 1, *map(int, hidden_sizes), 1], last_relu=False)

    def afterstates(self, x: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor, torch.Tensor]:
        """The afterstate of each action, raw (metres, radians), from a batch of scaled states:
        (robot part (B, A, 6), lasers (B, A, n), humans (B, A, k, 5): x, y, vx, vy, radius, present (B, k))."""
        raw = x / self.scale + self.offset
        n, k = self.lasers, self.human_k
        lasers, target, odometry, humans = raw.split([n, 3, 3, HUMAN_SLOT * k], dim=1)
        humans = humans.reshape(-1, k, HUMAN_SLOT)
        advance, turn = self.moves[:, 0], self.moves[:, 1]  # (A,)
        ahead, left = arc(advance, turn)
        c, s = torch.cos(turn), torch.sin(turn)

        def moved(px, py):  # a point of the robot's frame, in its frame after each action (broadcast on A last)
            qx, qy = px - ahead, py - left
            return c * qx + s * qy, -s * qx + c * qy

        def turned(vx, vy):  # a vector, in the frame after each action
            return c * vx + s * vy, -s * vx + c * vy

        d, sin_b, cos_b = (t[:, None] for t in target.unbind(1))
        tx, ty = moved(d * cos_b, d * sin_b)  # (B, A)
        distance = torch.sqrt(tx * tx + ty * ty).clamp_min(1e-6)
        mx, my = turned(ahead, left)
        robot = torch.stack([distance, ty / distance, tx / distance, mx.expand_as(tx), my.expand_as(tx),
                             turn.expand_as(tx)], dim=2)
        # pedestrians at constant velocity: their own step is the relative one plus the robot's
        hx, hy, vx, vy, radius = (t[..., None] for t in humans.unbind(2))  # (B, k, 1)
        vx, vy = vx + odometry[:, None, 0:1], vy + odometry[:, None, 1:2]
        nx, ny = moved(hx + vx, hy + vy)  # (B, k, A)
        nvx, nvy = turned(vx, vy)
        people = torch.stack([nx, ny, nvx, nvy, radius.expand_as(nx)], dim=3).transpose(1, 2)  # (B, A, k, 5)
        # the laser ring: each hit point from the new pose, then the ring turned
        px, py = lasers * torch.cos(self.angles), lasers * torch.sin(self.angles)  # (B, n)
        rings = []
        for a, shift in enumerate(self.shifts):
            qx, qy = px - ahead[a], py - left[a]
            ring = torch.sqrt(qx * qx + qy * qy).clamp(0.0, self.laser_range)
            rings.append(torch.roll(ring, -shift, dims=1) if shift else ring)
        return robot, torch.stack(rings, dim=1), people, humans[..., 4] > 0

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        """Q-values (batch, actions): the value of each action's afterstate."""
        robot, lasers, people, present = self.afterstates(x)
        b, a = robot.shape[:2]
        centre = torch.sqrt(people[..., 0] ** 2 + people[..., 1] ** 2)
        edge = centre - people[..., 4] - self.robot_radius
        scales = people.new_tensor([POSITION_SCALE, POSITION_SCALE, STEP_SCALE, STEP_SCALE, 0.3])
        features = torch.cat([people / scales, (centre / POSITION_SCALE)[..., None], edge[..., None]], dim=3)
        robot_in = robot / robot.new_tensor([POSITION_SCALE, 1, 1, STEP_SCALE, STEP_SCALE, 1])
        k = people.shape[2]
        e = self.each(torch.cat([robot_in[:, :, None].expand(b, a, k, 6), features], dim=3))  # (B, A, k, E)
        mask = present[:, None, :, None].expand(b, a, k, 1).float()
        count = mask.sum(dim=2, keepdim=True)
        mean = (e * mask).sum(dim=2, keepdim=True) / count.clamp_min(1.0)
        score = self.attention(torch.cat([e, mean.expand_as(e)], dim=3))
        score = score.masked_fill(mask == 0, -1e9)
        weight = torch.softmax(score, dim=2) * mask
        pooled = (weight * e).sum(dim=2)  # (B, A, E); zero with no pedestrian
        nearest = edge.masked_fill(~present[:, None, :].expand(b, a, k), self.laser_range).amin(dim=2)
        ring = self.laser_net(lasers / self.laser_range)
        head = torch.cat([robot_in, ring, pooled, nearest[..., None].clamp(max=self.laser_range)], dim=2)
        return self.value(head).squeeze(2)
