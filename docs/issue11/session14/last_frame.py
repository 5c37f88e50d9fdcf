"""Print each 2 px point's last frame (decided with the held arm): status, "none" and the objects' probabilities.

Usage: python docs/issue11/session14/last_frame.py POINTS.jsonl[.gz] ...   (* = on the pointed placard)
"""
import sys

sys.path.insert(0, "docs/issue11/session13/scripts")
from fuse import load_points  # noqa: E402

for p in load_points(sys.argv[1:]):
    if p["noise"] != 2.0:
        continue
    f = p["frames"][-1]
    objs = sorted(f["objects"], key=lambda o: -o[3])
    top = " ".join(f"{o[3]:.2f}{'*' if o[4] else ''}" for o in objs[:4])
    print(f"{p['family']:13s} scene {p['scene']} point {p['point']} {f['status']:15s} none {f['none'] or 0:.2f}  objects {top}")
