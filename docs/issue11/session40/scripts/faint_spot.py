import numpy as np, sys
sys.path.insert(0, ".")
from dip3d_vehicle.perception.blobs import BlobFinder
from test_selection import RIG, project
from test_blobs import WEDGE
def water(seed, grain):
    rng = np.random.default_rng(seed)
    img = np.empty((1200, 1600, 3), np.float32); img[:] = (120, 100, 40)
    img += rng.normal(0.0, grain, img.shape)
    return img
def spot(img, c, half, delta):
    x, y = int(round(c[0])), int(round(c[1]))
    img[y-half:y+half+1, x-half:x+half+1] += delta
for delta in (3, 4, 5, 6, 8):
    for grain in (0.3, 0.5):
        L, R = water(1, grain), water(2, grain)
        p = np.array([1.0, 0.0, 3.0])
        spot(L, project(p)[0], 4, delta); spot(R, project(p, -0.12)[0], 4, delta)
        L = np.clip(np.round(L), 0, 255).astype(np.uint8); R = np.clip(np.round(R), 0, 255).astype(np.uint8)
        out = []
        for mc in (3.0, 2.5):
            b = BlobFinder(min_contrast=mc).find(L, R, WEDGE, RIG)
            near = np.linalg.norm(b.xyz_m - p, axis=1) < 0.15 if len(b) else np.zeros(0, bool)
            out.append((len(b), bool(near.any())))
        print(delta, grain, out)
for grain in (0.3, 0.5, 1.0, 1.5, 3.0):
    tot = 0
    for s in range(5):
        L, R = water(10+s, grain), water(20+s, grain)
        L = np.clip(np.round(L), 0, 255).astype(np.uint8); R = np.clip(np.round(R), 0, 255).astype(np.uint8)
        tot += len(BlobFinder(min_contrast=2.5).find(L, R, WEDGE, RIG))
    print("water only", grain, tot)
