"""The latest campaign run of each layout and seed (docs/issue11/session*/campaigns, run from the repository root)."""
import glob, json, os


def latest_runs(skip=()):
    """Return {(layout name, seed): run record} from the highest session holding it; paths containing a ``skip`` part
    are left out."""
    latest = {}
    for f in sorted(glob.glob("docs/issue11/session*/campaigns/**/default_variant_*.txt", recursive=True)):
        if any(s in f for s in skip):
            continue
        name, session = os.path.basename(f)[8:-4], int(f.split("/")[2][7:])
        for line in open(f):
            if line.startswith('{"seed"'):
                d = json.loads(line)
                if (name, d["seed"]) not in latest or session >= latest[(name, d["seed"])][0]:
                    latest[(name, d["seed"])] = (session, d)
    return {k: d for k, (_, d) in latest.items()}
