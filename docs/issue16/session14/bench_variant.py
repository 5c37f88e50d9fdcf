"""Run the bench's default profile with parameter overrides on the cached bench frames; print fps/cpu/accuracy/stages."""
import json, pickle, sys
sys.path.insert(0, '/work/main')
from dip3d_vehicle import bench
data = pickle.load(open('/tmp/s14/frames.pkl', 'rb'))
over = dict(kv.split('=', 1) for kv in sys.argv[2:])
from dip3d_vehicle.config import load_params
import time
orig = bench.Perception if hasattr(bench,'Perception') else None
walls = []
_mk = bench.make_perception
def mk(*a, **k):
    p, pose = _mk(*a, **k)
    proc = p.process
    def process(l, r):
        t0 = time.perf_counter(); res = proc(l, r); walls.append(((time.perf_counter()-t0)*1e3, res.timings_ms, getattr(res,'candidates_followed',None)))
        return res
    p.process = process
    return p, pose
bench.make_perception = mk
r = bench.run_profile(sys.argv[1], data, over or None)
walls = walls[6:]
order = sorted(range(len(walls)), key=lambda i: -walls[i][0])[:6]
for i in order: print(i, round(walls[i][0]), walls[i][2], {k: round(v,1) for k,v in walls[i][1].items()})
st = {k: v['median'] for k, v in r['stages_ms'].items()}
print(json.dumps({'over': over, 'fps': r['fps'], 'cpu': r['cpu_ms_per_frame'], 'p50': r['latency_ms']['p50'], 'p99': r['latency_ms']['p99'],
                  'correct': r['correct'], 'status': r['status'], 'stages': st}))
