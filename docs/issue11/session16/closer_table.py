"""Summarise closer_look.py lines per scenario and forward offset (frames, arm in view, pointed placard found, leans).

Usage: python docs/issue11/session16/closer_table.py FILE.jsonl [FILE ...]
"""
from __future__ import annotations

import collections
import json
import sys

import numpy as np


def main(paths: list[str]) -> None:
    groups = collections.defaultdict(list)
    for path in paths:
        for line in open(path):
            row = json.loads(line)
            groups[(row["scenario"], row["forward_m"])].append(row)
    print("scenario     forward_m frames arm_in_view pointed_found pointed_leads other>=0.8  median p(pointed/other/none)")
    for (scenario, off), rows in sorted(groups.items()):
        probs = [r["p_pointed_other_none"] for r in rows if r["p_pointed_other_none"]]
        leads = sum(p[0] > max(p[1], p[2]) for p in probs)
        sure_other = sum(p[1] >= 0.8 for p in probs)
        med = np.median(np.array(probs), axis=0).round(2).tolist() if probs else None
        print(f"{scenario:12s} {off:9.1f} {len(rows):6d} {sum(r['arm_in_view'] for r in rows):11d} "
              f"{sum(r['on_target'] > 0 for r in rows):13d} {leads:13d} {sure_other:10d}  {med}")


if __name__ == "__main__":
    main(sys.argv[1:])
