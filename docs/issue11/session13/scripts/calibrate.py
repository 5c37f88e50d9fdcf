"""How many independent looks are n frames of a held point worth? Fit it on recorded points.

For every point (``points.py``) and every n, the frames' mean log probability per hypothesis
(``PointFusion.posterior(1 / n)``: the frames counted as one) is scaled by beta and soft-maxed; beta
is fitted by maximum likelihood of the true hypothesis (the placard's, or "none" when no object of
the point lay on it). beta = 1: the frames are one look; beta = n: independent looks. Also prints
the reliability of the best hypothesis' one-look posterior (binned).

Usage: python docs/issue11/session13/scripts/calibrate.py FILE.jsonl ... [--share] [--bias]
(--share: beta per bin of the frames' noise share; --bias: beta fitted with an extra log score for "none")
"""
import argparse
import math
import sys

import numpy as np

sys.path.insert(0, ".")
sys.path.insert(0, "docs/issue11/session13/scripts")
from behaviours.fusion import NONE, PointFusion  # noqa: E402
from fuse import BASE, fake_result, load_points  # noqa: E402

NS_ = (4, 6, 8, 12, 16, 20)
BETAS = np.arange(0.5, 12.01, 0.25)


def fused(point: dict):
    """Yield (n, fusion) after each frame of a point that said something, fused as the mission does."""
    fusion = PointFusion(**BASE)
    for i, rec in enumerate(point["frames"]):
        if fusion.add(fake_result(rec), 0.1 * i) is not None:
            yield len(fusion.frames), fusion


def keys_and_truth(fusion: PointFusion) -> tuple[list, int]:
    """Return the hypothesis keys ("none" last) and the index of the true one (the placard's, else "none")."""
    keys = [h.key for h in fusion.hypotheses] + [NONE]
    right = [h for h in fusion.hypotheses if h.obj is not None and h.obj.on_target]
    return keys, (keys.index(max(right, key=lambda h: h.weight).key) if right else len(keys) - 1)


def one_look(point: dict) -> dict:
    """Return {n: (mean log probability per hypothesis, index of the truth)} for the n in ``NS_``."""
    out = {}
    for n, fusion in fused(point):
        if n in NS_:
            _, truth = keys_and_truth(fusion)
            out[n] = (np.array([h.log_sum for h in fusion.hypotheses] + [fusion.none_log_sum]) / n, truth)
    return out


def frame_logs(point: dict, n: int) -> tuple[np.ndarray, int]:
    """Return the (frames, hypotheses) floored log probabilities of the first n frames and the truth index."""
    for k, fusion in fused(point):
        if k == n:
            break
    keys, truth = keys_and_truth(fusion)
    arr = np.array([[math.log(max(f.probabilities.get(key, 0.0), BASE["floor_p"])) for key in keys]
                    for f in fusion.frames])
    return arr, truth


def nll(beta: float, rows: list, bias: float = 0.0) -> float:
    """Return the mean negative log likelihood of the truth at scale beta ("none", last, gets ``bias`` more)."""
    total = 0.0
    for logs, t in rows:
        z = beta * logs
        z[-1] += bias
        z = z - z.max()
        total -= z[t] - math.log(np.exp(z).sum())
    return total / len(rows)


def fitted(rows: list, betas=BETAS) -> float:
    """Return the beta of least NLL on ``rows``."""
    return float(betas[int(np.argmin([nll(b, rows) for b in betas]))])


def beta_report(per_n: dict) -> None:
    """Print the fitted beta per n and the one-look reliability at n = 8."""
    for n in NS_:
        rows = per_n[n]
        if rows:
            b, cur = fitted(rows), min(0.5 * n, 4.0)
            print(f"n {n:2d}: {len(rows)} points, fitted beta {b:.2f} (nll {nll(b, rows):.3f}; beta 1: {nll(1.0, rows):.3f}; "
                  f"current {cur:.1f}: {nll(cur, rows):.3f})")
    print("reliability of the one-look posterior of the best hypothesis (n = 8):")
    bins = [0.0, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.01]
    for lo, hi in zip(bins, bins[1:]):
        hit = [(int(np.argmax(l)) == t) for l, t in per_n[8]
               if lo <= (np.exp(l - l.max()) / np.exp(l - l.max()).sum()).max() < hi]
        if hit:
            print(f"  one-look {lo:.1f}-{hi:.1f}: {len(hit):4d} points, best is right in {np.mean(hit):6.1%}")


def noise_share(arr: np.ndarray) -> float:
    """Return the estimated share of the frames' measurement noise in one look's doubt (0..1).

    The per-frame log-odds of the two leading hypotheses vary with the measurement noise only (the
    pointing error is the same in every frame): in the linear-Gaussian picture their variance over
    the frames is D * f and their mean about D / 2, D the pair's separation in log-odds units and
    f = s^2 / (sigma_p^2 + s^2) the noise share.
    """
    top = np.argsort(arr.mean(axis=0))[::-1][:2]
    odds = arr[:, top[0]] - arr[:, top[1]]
    sep = max(2.0 * abs(float(odds.mean())), 1e-6)
    return float(min(1.0, odds.var(ddof=1) / sep)) if len(odds) > 1 else 1.0


def share_report(points: list, n: int) -> None:
    """Print the fitted beta per noise-share bin, and the NLL of beta = 1 / (1 - f + f / n)."""
    rows = []
    for p in points:
        arr, t = frame_logs(p, n)
        if len(arr) == n:
            rows.append((arr.mean(axis=0), t, noise_share(arr), p["family"]))
    print(f"noise share at n = {n} ({len(rows)} points):")
    for lo, hi in ((0, 0.05), (0.05, 0.15), (0.15, 0.3), (0.3, 0.6), (0.6, 1.01)):
        inside = [r for r in rows if lo <= r[2] < hi]
        if len(inside) >= 5:
            fams = {}
            for r in inside:
                fams[r[3]] = fams.get(r[3], 0) + 1
            print(f"  f {lo:.2f}-{hi:.2f}: {len(inside):4d} points, fitted beta {fitted([r[:2] for r in inside]):.2f}  {fams}")
    pairs = [r[:2] for r in rows]
    model = sum(nll(1.0 / (1.0 - f + f / n), [(l, t)]) for l, t, f, _ in rows) / len(rows)
    print(f"  nll: beta from the noise share {model:.3f}; current {nll(min(0.5 * n, 4.0), pairs):.3f}; "
          f"one look {nll(1.0, pairs):.3f}")


def bias_report(per_n: dict) -> None:
    """Print beta and an extra log score for "none" fitted together, and the bias alone at today's beta."""
    biases = np.arange(-1.0, 4.01, 0.25)
    for n in NS_:
        rows = per_n[n]
        best = min((nll(b, rows, c), b, c) for b in np.arange(0.5, 8.01, 0.25) for c in biases)
        cur = min(0.5 * n, 4.0)
        bc = min((nll(cur, rows, c), c) for c in biases)
        print(f"n {n:2d}: {len(rows)} points: fitted beta {best[1]:.2f} none bias {best[2]:.2f} (nll {best[0]:.3f}); "
              f"current beta {cur:.1f}: bias {bc[1]:.2f} nll {bc[0]:.3f}, no bias {nll(cur, rows):.3f}")


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("files", nargs="+")
    ap.add_argument("--share", action="store_true")
    ap.add_argument("--bias", action="store_true")
    a = ap.parse_args()
    points = load_points(a.files)
    if a.share:
        for n in (6, 8, 12):
            share_report(points, n)
        return
    per_n = {n: [] for n in NS_}
    for p in points:
        for n, row in one_look(p).items():
            per_n[n].append(row)
    (bias_report if a.bias else beta_report)(per_n)


if __name__ == "__main__":
    main()
