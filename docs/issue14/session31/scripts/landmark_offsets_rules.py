"""How BlazePose's arm landmark offsets (``landmark_offsets_census.py``) spread, and what reaches the arm's direction.

    python docs/issue14/session31/scripts/landmark_offsets_rules.py CENSUS.jsonl[.gz] ...

Frames where every landmark lies within 0.3 m of its joint (the pointing arm read). Per joint: the offset's
RMS per image axis (m). Across the arm: the wrist's offset minus the shoulder's, across the truth shoulder-to-wrist
line (m), which is what turns the arm's image direction; the selector's model (``blazepose.keypoint_sigma_m``,
independent per joint) gives it an RMS of sqrt(2) x sigma.
"""
import gzip, json, sys
import numpy as np

rows = []
for f in sys.argv[1:]:
    with (gzip.open(f, "rt") if f.endswith(".gz") else open(f)) as fh:
        rows += [json.loads(l) for l in fh]
off = np.array([r["offset_px"] for r in rows]) / np.array([r["px_per_m"] for r in rows])[:, None, None]
keep = np.all(np.linalg.norm(off, axis=2) < 0.3, axis=1)
off = off[keep]
tru = np.array([r["truth_px"] for r in rows])[keep]
print(f"{len(rows)} frames, {keep.sum()} with the pointing arm read")
for k, name in enumerate(("shoulder", "elbow", "wrist")):
    rms = np.sqrt(np.mean(off[:, k] ** 2, axis=0))
    print(f"  {name:8s} offset RMS per axis (x, y) {rms[0]:.3f} {rms[1]:.3f} m; |offset| median {np.median(np.linalg.norm(off[:, k], axis=1)):.3f} m")
u = tru[:, 2] - tru[:, 0]
u /= np.linalg.norm(u, axis=1, keepdims=True)
n = np.c_[-u[:, 1], u[:, 0]]
for a, b, label in ((0, 2, "wrist - shoulder"), (1, 2, "wrist - elbow"), (0, 1, "elbow - shoulder")):
    diff = off[:, b] - off[:, a]
    across = np.einsum("ij,ij->i", diff, n)
    along = np.einsum("ij,ij->i", diff, u)
    print(f"  {label:16s} across the arm: RMS {np.sqrt(np.mean(across ** 2)):.3f} m, p90 |.| {np.percentile(np.abs(across), 90):.3f};"
          f" along: RMS {np.sqrt(np.mean(along ** 2)):.3f} m")
c = np.corrcoef(np.einsum("ij,ij->i", off[:, 0], n), np.einsum("ij,ij->i", off[:, 2], n))[0, 1]
print(f"  correlation of the shoulder's and wrist's offsets across the arm: {c:.2f}")
print("  the model, independent per joint, sigma 0.05 m: across RMS", round(np.sqrt(2) * 0.05, 3))
ppm = np.array([r["px_per_m"] for r in rows])[keep]
across_m = np.einsum("ij,ij->i", off[:, 2] - off[:, 0], n)
across_px = across_m * ppm
depth = 902.5 / ppm                  # the simulator's rectified focal length, pixels
print("wrist - shoulder across the arm, by the body's depth: frames, RMS m, p90 m, RMS px, p90 px")
for lo, hi in ((0.0, 2.0), (2.0, 2.5), (2.5, 3.0), (3.0, 3.5), (3.5, 4.5), (4.5, 6.0), (0.0, 99.0)):
    sel = (depth >= lo) & (depth < hi)
    if sel.any():
        a, p = across_m[sel], across_px[sel]
        print(f"  {lo:.1f}-{hi:.1f} m: {sel.sum():5d}  {np.sqrt(np.mean(a ** 2)):.3f} {np.percentile(np.abs(a), 90):.3f}"
              f"  {np.sqrt(np.mean(p ** 2)):5.1f} {np.percentile(np.abs(p), 90):5.1f}")
