"""fam.py with the head's match (as the shoulder's stand-in) moved toward the camera by HEAD_OFF metres (env)."""
import os, sys
sys.path.insert(0, "docs/issue11/session33/scripts")
from dip3d_vehicle.perception import given_arm as G
off = float(os.environ.get("HEAD_OFF", "0"))
oh = G.head_disparity
def hd(head_px, left, right, body, sign, f, b):
    r = oh(head_px, left, right, body, sign, f, b)
    if r is None or off == 0: return r
    fb = f * b
    return sign * fb / (fb / abs(r[0]) - off), r[1]
G.head_disparity = hd
import fam
n, seed0 = int(sys.argv[1]), int(sys.argv[2])
noise = tuple(float(x) for x in sys.argv[3].split(","))
print(fam.summary(fam.tally_default(n, seed0, noise, sys.argv[4:]), f"{seed0} off {off}", noise))
