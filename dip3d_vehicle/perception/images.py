"""Reading and checking input images at the edge (one clear ImageError per problem)."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np

from ..errors import ImageError

__all__ = ["read_image", "write_image", "check_pair", "grey"]


def read_image(path: str | Path) -> np.ndarray:
    """Read an image file as HxWx3 uint8 BGR; raise ImageError naming the file if it cannot."""
    path = Path(path)
    if not path.is_file():
        raise ImageError(f"{path}: image file not found")
    data = np.fromfile(str(path), dtype=np.uint8)
    img = cv2.imdecode(data, cv2.IMREAD_COLOR) if data.size else None
    if img is None:
        raise ImageError(f"{path}: not a readable image (corrupt or unsupported format)")
    return img


def write_image(path: str | Path, image: np.ndarray) -> Path:
    """Write an image (format from the extension); raise ImageError naming the file if it cannot."""
    path = Path(path)
    try:
        ok = cv2.imwrite(str(path), image)
    except cv2.error:
        ok = False
    if not ok:
        raise ImageError(f"{path}: cannot write the image (folder missing, not writable, or an extension "
                         f"OpenCV cannot write: use .png or .jpg)")
    return path


def check_pair(left: np.ndarray, right: np.ndarray, left_name: str, right_name: str) -> None:
    """Raise ImageError if the two images of a pair differ in size."""
    if left.shape[:2] != right.shape[:2]:
        raise ImageError(f"{right_name}: size {right.shape[1]}x{right.shape[0]} differs from "
                         f"{left_name} ({left.shape[1]}x{left.shape[0]})")


def grey(image: np.ndarray, copy: bool = False) -> np.ndarray:
    """Return a single-channel uint8 image (BGR converted; grey passed through, or copied if ``copy``)."""
    if image.ndim == 2:
        return np.array(image, copy=True) if copy else image
    return cv2.cvtColor(image, cv2.COLOR_BGR2GRAY)
