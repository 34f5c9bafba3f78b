"""Pictures of the auto-encoder at work (thesis Figs. 6.12-6.14, 6.20-6.22).

* ``save_reconstruction_pairs``: camera frames (top row) above their reconstructions (bottom
  row); a stack of gray frames is drawn as its frames side by side, oldest first.
* ``append_srl_losses`` / ``plot_srl_losses``: the reconstruction loss (Eq. 4.10) of every
  iteration of every update, as CSV and as a curve.
* ``plot_latents``: 2-D PCA and t-SNE maps of latent vectors, coloured by the episode's
  target and by the step's reward.
"""

from __future__ import annotations

import csv
import io
from pathlib import Path

import numpy as np

from agents.files import atomic_write_bytes, save_figure


def _save_png(fig_or_image, path: Path) -> None:
    """Save a matplotlib figure or a PIL image to ``path`` atomically."""
    path.parent.mkdir(parents=True, exist_ok=True)
    save_figure(fig_or_image, path)


def _tile(frame: np.ndarray) -> np.ndarray:
    """(H, W, 3) RGB stays; (H, W, N) gray frames become (H, N*W, 3), oldest on the left."""
    if frame.shape[-1] == 3:
        return frame
    strip = np.concatenate([frame[..., k] for k in range(frame.shape[-1])], axis=1)
    return np.repeat(strip[..., None], 3, axis=2)


def pair_image(frames: np.ndarray, reconstructions: np.ndarray, scale: int = 4, gap: int = 2) -> np.ndarray:
    """One uint8 image: each frame above its reconstruction, samples left to right."""
    tiles = [(_tile(f), _tile(r)) for f, r in zip(frames, reconstructions)]
    h, w = tiles[0][0].shape[:2]
    out = np.full((2 * h + gap, len(tiles) * (w + gap) - gap, 3), 255, dtype=np.uint8)
    for k, (f, r) in enumerate(tiles):
        x = k * (w + gap)
        out[:h, x:x + w], out[h + gap:, x:x + w] = f, r
    return np.kron(out, np.ones((scale, scale, 1), dtype=np.uint8))


def save_reconstruction_pairs(frames: np.ndarray, reconstructions: np.ndarray, path: Path) -> None:
    """Save frames above their reconstructions as one PNG at ``path``."""
    from PIL import Image

    _save_png(Image.fromarray(pair_image(frames, reconstructions)), Path(path))


def append_srl_losses(path: Path, update: int, episode: int, losses: list[float]) -> None:
    """Add one row per iteration: update number, episode, iteration, mean loss of its batches."""
    path = Path(path)
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    if path.exists():
        out.write(path.read_text())
    else:
        writer.writerow(["update", "episode", "iteration", "loss"])
    writer.writerows([update, episode, i + 1, f"{loss:.6g}"] for i, loss in enumerate(losses))
    atomic_write_bytes(path, out.getvalue().encode())


def plot_srl_losses(csv_path: Path, png_path: Path, title: str = "") -> None:
    """Draw the losses of ``csv_path`` (``append_srl_losses``), one curve per update, to ``png_path``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    with open(csv_path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        return
    fig, ax = plt.subplots(figsize=(7, 4), dpi=100)
    for update in sorted({int(r["update"]) for r in rows}):
        mine = [r for r in rows if int(r["update"]) == update]
        ax.plot([int(r["iteration"]) for r in mine], [float(r["loss"]) for r in mine], marker=".",
                label=f"update {update} (episode {mine[0]['episode']})")
    ax.set_xlabel("iteration")
    ax.set_ylabel("reconstruction loss (Eq. 4.10, per image)")
    ax.set_yscale("log")
    ax.grid(alpha=0.3)
    ax.legend()
    ax.set_title(f"{title}: auto-encoder" if title else "auto-encoder")
    fig.tight_layout()
    _save_png(fig, Path(png_path))
    plt.close(fig)


def embed_2d(latents: np.ndarray, method: str, seed: int = 0) -> np.ndarray:
    """(N, 2) PCA or t-SNE coordinates of (N, latent) vectors."""
    from sklearn.decomposition import PCA
    from sklearn.manifold import TSNE

    if method == "pca":
        return PCA(n_components=2, random_state=seed).fit_transform(latents)
    if method == "tsne":
        perplexity = float(min(30.0, max(2.0, (len(latents) - 1) / 3)))
        return TSNE(n_components=2, perplexity=perplexity, init="pca", random_state=seed).fit_transform(latents)
    raise ValueError(f"unknown embedding {method!r}; valid: pca, tsne")


def plot_latents(latents: np.ndarray, targets: np.ndarray, rewards: np.ndarray, out_dir: Path,
                 title: str = "", max_points: int = 3000, seed: int = 0) -> list[Path]:
    """latent_pca.png and latent_tsne.png: each a map coloured by target (left) and reward (right)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    latents, targets, rewards = np.asarray(latents), np.asarray(targets), np.asarray(rewards)
    if len(latents) > max_points:  # t-SNE is quadratic in the number of points
        keep = np.sort(np.random.default_rng(seed).choice(len(latents), max_points, replace=False))
        latents, targets, rewards = latents[keep], targets[keep], rewards[keep]
    written = []
    for method, label in (("pca", "PCA"), ("tsne", "t-SNE")):
        xy = embed_2d(latents, method, seed)
        fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.6), dpi=100)
        for t in np.unique(targets):
            sel = targets == t
            a.scatter(xy[sel, 0], xy[sel, 1], s=5, alpha=0.7, label=f"target {int(t)}")
        a.legend(markerscale=3)
        a.set_title("coloured by target")
        lim = float(np.percentile(np.abs(rewards), 98)) or 1.0
        sc = b.scatter(xy[:, 0], xy[:, 1], c=rewards, s=5, cmap="coolwarm_r", vmin=-lim, vmax=lim)
        fig.colorbar(sc, ax=b, label="reward of the step")
        b.set_title("coloured by reward")
        fig.suptitle(f"{title}: latent states, {label}" if title else f"latent states, {label}")
        fig.tight_layout()
        path = Path(out_dir) / f"latent_{method}.png"
        _save_png(fig, path)
        plt.close(fig)
        written.append(path)
    return written
