"""default only, given noise levels, with KEY=VALUE overrides: detectable / undetectable / confidently wrong."""
import sys, tempfile
from pathlib import Path
sys.path.insert(0, "tests/perception")
import scene_families as sf
n, seed0 = int(sys.argv[1]), int(sys.argv[2])
noise = tuple(float(x) for x in sys.argv[3].split(","))
over = sys.argv[4:]
tally = sf.Tally()
with tempfile.TemporaryDirectory() as tmp:
    for family in sf.FAMILIES:
        sf.tally_family(Path(tmp), family, n, 8, seed0, noise_px=noise, profiles=("default",), tally=tally, overrides=over)
for s in noise:
    det = tally.merged("default", s, ("line_of_sight", "far", "elbow", "far_diver"))
    und = tally.merged("default", s, ("undetectable",))
    allc = tally.merged("default", s)
    print(f"{seed0} {' '.join(over)} noise {s}: detectable {det} correct {sf.rate(det,'correct'):.1%}; undetectable {sf.rate(und,'correct'):.1%} {und}; conf wrong {sf.rate(allc,'confident_wrong'):.2%}")
print(sf.report(tally, noise_px=noise))
