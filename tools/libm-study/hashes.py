#!/usr/bin/env python3
"""hashes.py A B: compare the actual state hashes of two check reports scene by scene."""
import json, sys
def load(d):
    r = json.load(open(f"reports/{d}/report.json"))
    return {s["scene"]: [(h["frame"], h["actual"]) for h in s["hashes"]] for s in r["scenes"]}
a, b = load(sys.argv[1]), load(sys.argv[2])
same = [s for s in a if s in b and a[s] == b[s]]
diff = [s for s in a if s in b and a[s] != b[s]]
print(f"{sys.argv[1]} vs {sys.argv[2]}: {len(same)} scenes with all checkpoint hashes equal, {len(diff)} differ: " +
      ", ".join(f"{s}@{next(fa for (fa, ha), (fb, hb) in zip(a[s], b[s]) if ha != hb)}" for s in diff))
