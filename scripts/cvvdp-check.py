#!/usr/bin/env python3
"""Checks `compare`'s ColorVideoVDP scores against the metric authors' PyTorch implementation.

For a `compare --path/--walk --every 1` output folder, reads each technique's frames and the
reference's (`frames/METHOD-NNNN.png`, `frames/reference-NNNN.png`, the images the report
shows), scores the same run of consecutive frames with `pycvvdp` (display `standard_fhd`, the
path's frame rate) and prints it beside the score in `metrics.json`.

    scripts/cvvdp-check.py OUT [--fps 30]

Needs `pip install cvvdp` (PyTorch; CPU is enough). Not part of the tests: it is how the
crate's port was checked here (the book, "In motion").
"""
import argparse
import json
import os
import sys

import numpy as np
from PIL import Image


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("--fps", type=float, default=30.0)
    args = ap.parse_args()
    try:
        import pycvvdp
        import torch
    except ImportError as e:
        sys.exit(f"cvvdp-check: {e} (pip install cvvdp)")
    metrics = json.load(open(os.path.join(args.out, "metrics.json")))
    metric = pycvvdp.cvvdp(display_name="standard_fhd", device=torch.device("cpu"))
    frames_dir = os.path.join(args.out, "frames")

    def load(name, n):
        return np.asarray(Image.open(os.path.join(frames_dir, f"{name}-{n:04d}.png")).convert("RGB"))

    print("method,frames,rust_jod,pytorch_jod,difference")
    for m in metrics["methods"]:
        if m.get("video_jod") is None:
            continue
        # The longest run of consecutive measured frames, as `compare` takes it.
        numbers = [p["frames"] for p in m["path"]]
        best, start = (0, 0), 0
        for k in range(len(numbers)):
            if k > 0 and numbers[k] != numbers[k - 1] + 1:
                start = k
            if k + 1 - start > best[1]:
                best = (start, k + 1 - start)
        run = numbers[best[0] : best[0] + best[1]]
        assert len(run) == m["video_frames"], (len(run), m["video_frames"])
        test = np.stack([load(m["name"], n) for n in run])
        ref = np.stack([load("reference", n) for n in run])
        q, _ = metric.predict(test, ref, dim_order="FHWC", frames_per_second=args.fps)
        q = float(q)
        print(f"{m['name']},{len(run)},{m['video_jod']:.5f},{q:.5f},{m['video_jod'] - q:+.5f}")


if __name__ == "__main__":
    main()
