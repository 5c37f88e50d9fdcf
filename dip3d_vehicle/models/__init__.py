"""Bundled neural models: where they are and a sha256 check before anything loads them.

The files are package data (see README.md / NOTICE / LICENSE here for provenance and licence).
"""

from __future__ import annotations

import hashlib
from pathlib import Path

from ..errors import ModelError

__all__ = ["MODELS", "MODELS_DIR", "model_path", "verify_model", "sha256_of"]

MODELS_DIR = Path(__file__).resolve().parent
"""Folder holding the bundled model files."""

MODELS: dict[str, tuple[str, str]] = {
    "pose_detection": ("pose_detection_fp16w.onnx",
                       "144a3ec0e9be9970b3c2539fc38135cdd5c1983c598c291de3f32b981175c761"),
    "pose_landmark_full": ("pose_landmark_full_fp16w.onnx",
                           "4deae559cb040b4f33937a29ca0f845073962785baebba4aa23ab19c3c26ca53"),
}
"""Model name -> (file name in MODELS_DIR, expected sha256 hex digest)."""

_VERIFIED: dict[tuple[str, int, int], str] = {}


def sha256_of(path: Path) -> str:
    """Return the sha256 hex digest of a file, read in 1 MiB blocks."""
    digest = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def verify_model(path: str | Path, expected_sha256: str) -> Path:
    """Return ``path`` if it exists and has the expected sha256, else raise ModelError.

    The result is cached per (path, size, mtime), so a file is hashed once per process.
    """
    path = Path(path)
    try:
        stat = path.stat()
    except OSError:
        raise ModelError(f"{path}: model file is missing (reinstall dip3d-vehicle or run "
                         f"tools/make_pose_models.py)") from None
    key = (str(path), stat.st_size, stat.st_mtime_ns)
    if _VERIFIED.get(key) != expected_sha256:
        actual = sha256_of(path)
        if actual != expected_sha256:
            raise ModelError(f"{path}: model file is altered or corrupt (sha256 {actual[:16]}..., "
                             f"expected {expected_sha256[:16]}...)")
        _VERIFIED[key] = expected_sha256
    return path


def model_path(name: str, folder: str | Path | None = None) -> Path:
    """Return the verified path of the bundled model ``name`` (optionally from another folder)."""
    if name not in MODELS:
        raise ModelError(f"unknown model {name!r} (expected one of {', '.join(MODELS)})")
    file_name, sha = MODELS[name]
    return verify_model(Path(folder or MODELS_DIR) / file_name, sha)
