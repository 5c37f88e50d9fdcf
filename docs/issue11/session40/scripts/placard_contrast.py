import sys, numpy as np, cv2
from dip3d_vehicle.config import load_params
from sitl.render import StereoRenderer
from sitl.scenario import load_scenario
scen, seed, pid = sys.argv[1], int(sys.argv[2]), sys.argv[3]
params = load_params("default")
sc = load_scenario(scen, seed)
v = sc.initial_vehicle_pose
with StereoRenderer(sc, params) as r:
    fr = r.render(v.north_m, v.east_m, v.depth_m, v.yaw_rad, sc.diver.start_s + 1.0)
P = np.asarray(fr.meta["placards"][int(pid)]["left_polygon_px"], float)
c = P.mean(0).astype(int); print("centre", c, "size px", P.max(0)-P.min(0))
g = cv2.cvtColor(fr.left, cv2.COLOR_BGR2GRAY) if fr.left.ndim == 3 else fr.left
x0, y0 = c - 40
crop = g[y0:y0+80, x0:x0+80]
print("crop min/max/median", crop.min(), crop.max(), np.median(crop))
inner = g[int(P[:,1].min()):int(P[:,1].max())+1, int(P[:,0].min()):int(P[:,0].max())+1]
print("placard region mean", inner.mean(), "surround median", np.median(crop))
big = cv2.resize(fr.left[y0:y0+80, x0:x0+80], (320, 320), interpolation=cv2.INTER_NEAREST)
cv2.imwrite("/tmp/crop.png", big)
