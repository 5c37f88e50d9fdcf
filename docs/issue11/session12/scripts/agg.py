import sys, json, collections
rows = [json.loads(l) for f in sys.argv[1:] for l in open(f) if l.startswith("{")]
variants = rows[0]["variants"]
tot = collections.defaultdict(lambda: collections.Counter())
for r in rows:
    for key, c in r["counts"].items():
        vi, kind, band, noise = key.split("|")
        tot[(int(vi), kind, noise)].update(c)
for vi, v in enumerate(variants):
    line = [f"{' '.join(v) or 'base':60s}"]
    for noise in ("0", "1", "2", "4"):
        d, u = tot[(vi, "det", noise)], tot[(vi, "und", noise)]
        alld = sum(d.values()) + sum(u.values())
        cw = (d["confident_wrong"] + u["confident_wrong"]) / max(alld, 1)
        line.append(f"{noise}px det {d['correct']/max(sum(d.values()),1):5.1%} und {u['correct']/max(sum(u.values()),1):5.1%} cw {cw:5.2%}")
    print(" | ".join(line))
