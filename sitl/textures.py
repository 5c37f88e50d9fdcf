"""Procedural textures: numbered placards with a rich random print (SIFT finds many features).

Everything is seeded; the same (number, seed, size) always gives the same pixels.
"""

from __future__ import annotations

import cv2
import numpy as np

__all__ = ["placard_texture", "mip_levels"]


_DISCS = ((250, 250, 250), (120, 235, 250), (170, 215, 250), (200, 250, 200), (230, 200, 250),
          (250, 230, 190))
"""Light BGR disc colours behind the number (white, yellow, peach, mint, pink, sky)."""


def _random_colour(rng: np.random.Generator) -> tuple[int, int, int]:
    """Return a saturated random BGR colour."""
    hsv = np.uint8([[[rng.integers(0, 180), rng.integers(120, 256), rng.integers(60, 256)]]])
    b, g, r = cv2.cvtColor(hsv, cv2.COLOR_HSV2BGR)[0, 0]
    return int(b), int(g), int(r)


def _shapes(img: np.ndarray, rng: np.random.Generator, count: int, r_lo: int, r_hi: int) -> None:
    """Draw ``count`` random filled circles, rectangles, triangles and strokes of radius r_lo..r_hi."""
    s = img.shape[0]
    for _ in range(count):
        kind = rng.integers(4)
        c = (int(rng.integers(0, s)), int(rng.integers(0, s)))
        r = int(rng.integers(r_lo, r_hi + 1))
        col = _random_colour(rng) if rng.random() < 0.8 else (int(rng.integers(0, 60)),) * 3
        if kind == 0:
            cv2.circle(img, c, r, col, -1, cv2.LINE_AA)
        elif kind == 1:
            cv2.rectangle(img, (c[0] - r, c[1] - r // 2), (c[0] + r, c[1] + r // 2), col, -1)
        elif kind == 2:
            pts = (np.array(c) + rng.integers(-r, r + 1, size=(3, 2))).astype(np.int32)
            cv2.fillConvexPoly(img, pts, col, cv2.LINE_AA)
        else:
            end = (np.array(c) + rng.integers(-2 * r, 2 * r + 1, size=2)).astype(int)
            cv2.line(img, c, (int(end[0]), int(end[1])), col, max(1, r // 4), cv2.LINE_AA)


def placard_texture(number: int, seed: int = 0, size_px: int = 512) -> np.ndarray:
    """Return a square BGR texture: a dark frame, a random multi-scale print and a big number.

    Args:
        number: the number printed in the middle.
        seed: texture seed (different placards should have different seeds).
        size_px: side length, pixels.

    Returns:
        (size_px, size_px, 3) uint8 BGR image.
    """
    rng = np.random.default_rng([int(seed), int(number), 7919])
    s = size_px
    img = np.full((s, s, 3), 235, np.uint8)
    k = s / 512.0
    _shapes(img, rng, 25, int(30 * k), int(70 * k))
    _shapes(img, rng, 90, int(10 * k), int(28 * k))
    _shapes(img, rng, 220, max(2, int(3 * k)), max(3, int(9 * k)))
    # The number on a light disc, as large as legibility allows. Disc colour, size and ring vary
    # per placard so that the discs of different placards are not identical features.
    centre = (s // 2, s // 2)
    disc = _DISCS[int(rng.integers(len(_DISCS)))]
    radius = int(s * rng.uniform(0.25, 0.31))
    cv2.circle(img, centre, radius, disc, -1, cv2.LINE_AA)
    if rng.random() < 0.7:
        cv2.circle(img, centre, radius, (20, 20, 20), max(2, int(rng.uniform(3, 12) * k)), cv2.LINE_AA)
    text = str(number)
    font, thick = cv2.FONT_HERSHEY_DUPLEX, max(2, int(22 * k))
    (tw, th), _ = cv2.getTextSize(text, font, 1.0, thick)
    scale = 0.30 * s / max(th, 1) if len(text) == 1 else 0.42 * s / max(tw, 1)
    (tw, th), _ = cv2.getTextSize(text, font, scale, thick)
    cv2.putText(img, text, (centre[0] - tw // 2, centre[1] + th // 2), font, scale, (15, 15, 15), thick,
                cv2.LINE_AA)
    border = max(2, int(0.03 * s))
    cv2.rectangle(img, (0, 0), (s - 1, s - 1), (25, 25, 25), border)
    return img


def mip_levels(texture: np.ndarray, min_px: int = 16) -> list[np.ndarray]:
    """Return the texture and its successive halvings (cv2.pyrDown) down to ``min_px``."""
    levels = [texture]
    while levels[-1].shape[0] // 2 >= min_px:
        levels.append(cv2.pyrDown(levels[-1]))
    return levels
