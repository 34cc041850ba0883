#!/usr/bin/env python3
"""Hostile scenes for the element graph's bound (docs/element-graph.md).

  scripts/hostile-scenes.py DIR

writes into DIR (with a copy of examples/art/rock.png):
  stacked-20k.json   20,000 sprites at one spot
  stacked-50k.json   50,000 sprites at one spot
  wide-100k.json     one sprite 3e9 px wide over 100,000 small ones
Each must optimize within 10 s and 1 GB:
  /usr/bin/time -v build/depthcull optimize DIR/stacked-50k.json -o /tmp/m.json --no-cache --stats
"""
import json, os, shutil, sys

def scene(elements):
    return {"viewport": {"x": 0, "y": 0, "width": 1024, "height": 768},
            "images": [{"id": "rock", "path": "rock.png"}],
            "elements": elements}

def write(path, s):
    with open(path, "w") as f:
        json.dump(s, f, separators=(",", ":"))

def main():
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    here = os.path.dirname(os.path.abspath(__file__))
    shutil.copy(os.path.join(here, "..", "examples", "art", "rock.png"), os.path.join(out, "rock.png"))
    for n in (20000, 50000):
        write(os.path.join(out, "stacked-%dk.json" % (n // 1000)),
              scene([{"image": "rock", "transform": [1, 0, 0, 1, 100, 100]} for _ in range(n)]))
    # 100,000 sprites on a 316-wide grid, 24 px apart (they overlap their
    # neighbours), and one sprite stretched to 3e9 px across them.
    els = [{"image": "rock", "transform": [6.25e7, 0, 0, 1, -9e8, 50]}]
    for k in range(100000):
        els.append({"image": "rock", "transform": [1, 0, 0, 1, (k % 316) * 24, (k // 316) * 24]})
    write(os.path.join(out, "wide-100k.json"), scene(els))

if __name__ == "__main__":
    main()
