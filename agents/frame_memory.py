"""The observation memory the auto-encoder trains on: camera frames stored as uint8.

The thesis ran out of memory and shrank its images; uint8 frames in one preallocated ring
buffer cost 32*32*3 = 3 KB per RGB frame (4 KB per 4-frame gray stack): 100,000 frames are
307 MB (410 MB stacked). ``nbytes`` reports the size.
"""

from __future__ import annotations

import numpy as np


class FrameMemory:
    """A ring buffer of ``capacity`` frames of one shape; the oldest are overwritten."""

    def __init__(self, capacity: int, frame_shape: tuple[int, ...]):
        if capacity < 1:
            raise ValueError(f"frame memory capacity must be >= 1, got {capacity}")
        self.frames = np.zeros((capacity, *frame_shape), dtype=np.uint8)
        self.capacity = capacity
        self.size = 0
        self.next = 0

    def add(self, frame: np.ndarray) -> None:
        if frame.dtype != np.uint8 or frame.shape != self.frames.shape[1:]:
            raise ValueError(f"expected a uint8 frame of shape {self.frames.shape[1:]}, got {frame.dtype} {frame.shape}")
        self.frames[self.next] = frame
        self.next = (self.next + 1) % self.capacity
        self.size = min(self.size + 1, self.capacity)

    def sample(self, batch_size: int, rng: np.random.Generator) -> np.ndarray:
        if self.size == 0:
            raise ValueError("the frame memory is empty")
        return self.frames[rng.integers(0, self.size, size=batch_size)]

    @property
    def nbytes(self) -> int:
        return int(self.frames.nbytes)

    def state_dict(self) -> dict:
        return {"frames": self.frames[: self.size].copy() if self.size < self.capacity else self.frames,
                "size": self.size, "next": self.next}

    def load_state_dict(self, state: dict) -> None:
        n = int(state["size"])
        self.frames[:n] = state["frames"][:n]
        self.size, self.next = n, int(state["next"])
