"""How many independent looks are n frames of a held point worth? Fit it on recorded points.

For every point (``points.py``) and every n, the frames' mean log probability per hypothesis
(``PointFusion.posterior(1 / n)``: the frames counted as one) is scaled by beta and soft-maxed; beta
is fitted by maximum likelihood of the true hypothesis (the placard's, or "none" when no object of
the point lay on it). beta = 1: the frames are one look; beta = n: independent looks. Also prints
the reliability of the best hypothesis' one-look posterior (binned).

Usage: python docs/issue11/session13/scripts/calibrate.py FILE.jsonl ...
"""
import json
import math
import sys

import numpy as np

sys.path.insert(0, ".")
sys.path.insert(0, "docs/issue11/session13/scripts")
from behaviours.fusion import NONE, PointFusion  # noqa: E402
from fuse import BASE, fake_result, read_lines  # noqa: E402

NS_ = (4, 6, 8, 12, 16, 20)


def one_look(point: dict) -> dict:
    """Return {n: (keys, mean log probability array, index of the truth)} over the point's first n frames."""
    fusion = PointFusion(**BASE)
    out = {}
    for i, rec in enumerate(point["frames"]):
        fusion.add(fake_result(rec), 0.1 * i)
        n = len(fusion.frames)
        if n in NS_ and n not in out:
            keys = [h.key for h in fusion.hypotheses] + [NONE]
            logs = np.array([h.log_sum for h in fusion.hypotheses] + [fusion.none_log_sum]) / n
            right = [h.key for h in fusion.hypotheses if h.obj is not None and h.obj.on_target]
            truth = keys.index(max(right, key=lambda k: fusion.hypothesis(k).weight)) if right else len(keys) - 1
            out[n] = (keys, logs, truth)
    return out


def nll(beta: float, rows: list) -> float:
    """Return the mean negative log likelihood of the truth at scale beta."""
    total = 0.0
    for logs, t in rows:
        z = beta * logs
        z = z - z.max()
        total -= z[t] - math.log(np.exp(z).sum())
    return total / len(rows)


def main() -> None:
    points = [json.loads(line) for f in sys.argv[1:] for line in read_lines(f) if line.strip()]
    per_n = {n: [] for n in NS_}
    for p in points:
        for n, (keys, logs, t) in one_look(p).items():
            per_n[n].append((logs, t))
    grid = np.arange(0.5, 12.01, 0.25)
    for n in NS_:
        rows = per_n[n]
        if not rows:
            continue
        costs = [nll(b, rows) for b in grid]
        b = grid[int(np.argmin(costs))]
        print(f"n {n:2d}: {len(rows)} points, fitted beta {b:.2f} (nll {min(costs):.3f}; beta 1: {nll(1.0, rows):.3f}; "
              f"current {min(0.5 * n, 4.0):.1f}: {nll(min(0.5 * n, 4.0), rows):.3f})")
    print("reliability of the one-look posterior of the best hypothesis (n = 8):")
    bins = [0.0, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.01]
    rows = per_n[8]
    for lo, hi in zip(bins, bins[1:]):
        hit = [(int(np.argmax(l)) == t) for l, t in rows
               if lo <= (np.exp(l - l.max()) / np.exp(l - l.max()).sum()).max() < hi]
        if hit:
            print(f"  one-look {lo:.1f}-{hi:.1f}: {len(hit):4d} points, best is right in {np.mean(hit):6.1%}")


if __name__ == "__main__" and not any(a.startswith("--") for a in sys.argv):
    main()


def frame_logs(point: dict, n: int):
    """Return (keys, (n_frames, H) per-frame floored log probabilities, truth index) over the first n frames."""
    fusion = PointFusion(**BASE)
    per_frame = []
    for i, rec in enumerate(point["frames"][:n]):
        if fusion.add(fake_result(rec), 0.1 * i) is None:
            continue
        per_frame.append(dict(fusion.frames[-1].probabilities))
    keys = [h.key for h in fusion.hypotheses] + [NONE]
    arr = np.array([[math.log(max(f.get(k, 0.0), BASE["floor_p"])) for k in keys] for f in per_frame])
    right = [h.key for h in fusion.hypotheses if h.obj is not None and h.obj.on_target]
    truth = keys.index(max(right, key=lambda k: fusion.hypothesis(k).weight)) if right else len(keys) - 1
    return keys, arr, truth


def noise_share(arr: np.ndarray) -> float:
    """Return the estimated share of the frames' measurement noise in one look's doubt (0..1).

    The per-frame log-odds of the two leading hypotheses vary with the measurement noise only (the
    pointing error is the same in every frame): in the linear-Gaussian picture their variance over
    the frames is D * f and their mean about D / 2, D the pair's separation in log-odds units and
    f = s^2 / (sigma_p^2 + s^2) the noise share.
    """
    mean = arr.mean(axis=0)
    top = np.argsort(mean)[::-1][:2]
    odds = arr[:, top[0]] - arr[:, top[1]]
    sep = max(2.0 * abs(float(odds.mean())), 1e-6)
    return float(min(1.0, odds.var(ddof=1) / sep)) if len(odds) > 1 else 1.0


def share_report(points: list, n: int = 8) -> None:
    """Print the fitted beta per noise-share bin, and the NLL of beta = 1 / (1 - f + f / n)."""
    rows = []
    for p in points:
        keys, arr, t = frame_logs(p, n)
        if len(arr) < n:
            continue
        rows.append((arr.mean(axis=0), t, noise_share(arr), p["family"]))
    grid = np.arange(0.5, 12.01, 0.25)
    print(f"noise share at n = {n} ({len(rows)} points):")
    for lo, hi in ((0, 0.05), (0.05, 0.15), (0.15, 0.3), (0.3, 0.6), (0.6, 1.01)):
        sub = [(l, t) for l, t, f, _ in rows if lo <= f < hi]
        if len(sub) < 5:
            continue
        costs = [nll(b, sub) for b in grid]
        fams = {}
        for _, _, f, fam in rows:
            if lo <= f < hi:
                fams[fam] = fams.get(fam, 0) + 1
        print(f"  f {lo:.2f}-{hi:.2f}: {len(sub):4d} points, fitted beta {grid[int(np.argmin(costs))]:.2f}  {fams}")
    model = sum(nll(1.0 / (1.0 - f + f / n), [(l, t)]) for l, t, f, _ in rows) / len(rows)
    cur = nll(min(0.5 * n, 4.0), [(l, t) for l, t, _, _ in rows])
    print(f"  nll: beta from the noise share {model:.3f}; current {cur:.3f}; one look {nll(1.0, [(l, t) for l, t, _, _ in rows]):.3f}")


if __name__ == "__main__" and "--share" in sys.argv:
    pts = [json.loads(line) for f in sys.argv[1:] if f != "--share" for line in read_lines(f) if line.strip()]
    for n in (6, 8, 12):
        share_report(pts, n)


def nll_bias(beta: float, bias: float, rows: list) -> float:
    """Mean NLL of the truth with "none" (the last hypothesis) given ``bias`` extra log score."""
    total = 0.0
    for logs, t in rows:
        z = beta * logs
        z[-1] += bias
        z = z - z.max()
        total -= z[t] - math.log(np.exp(z).sum())
    return total / len(rows)


if __name__ == "__main__" and "--bias" in sys.argv:
    pts = [json.loads(line) for f in sys.argv[1:] if not f.startswith("--") for line in read_lines(f) if line.strip()]
    per_n = {n: [] for n in NS_}
    for p in pts:
        for n, (keys, logs, t) in one_look(p).items():
            per_n[n].append((logs, t))
    for n in NS_:
        rows = per_n[n]
        best = min(((nll_bias(b, c, rows), b, c) for b in np.arange(0.5, 8.01, 0.25) for c in np.arange(-1.0, 4.01, 0.25)))
        cur = min(0.5 * n, 4.0)
        bc = min(((nll_bias(cur, c, rows), c) for c in np.arange(-1.0, 4.01, 0.25)))
        print(f"n {n:2d}: {len(rows)} points: fitted beta {best[1]:.2f} none bias {best[2]:.2f} (nll {best[0]:.3f}); "
              f"current beta {cur:.1f}: bias {bc[1]:.2f} nll {bc[0]:.3f}, no bias {nll(cur, rows):.3f}")
