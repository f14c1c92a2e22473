#!/usr/bin/env python3
"""Plots the contact sweep of `cornertree scaling --contact-sweep --json R`.

Usage: python3 tools/plot_contact_sweep.py R.json OUT.png   (needs matplotlib)

Left: median ms per frame of parry3d and each method against the gap to the
surface (negative: that deep into it). Right: each method's speed-up over
parry3d. Every figure is read from the report; nothing is computed here but
the axes.
"""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(report, out):
    with open(report) as f:
        rows = json.load(f)["by_contact_gap"]
    if not rows:
        sys.exit(f"{report}: no contact sweep in this report (scaling --contact-sweep)")
    rows.sort(key=lambda b: -b["gap_metres"])
    gaps = [100.0 * b["gap_metres"] for b in rows]
    methods = [m["method"] for m in rows[0]["methods"]]
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.2))
    left.plot(gaps, [b["parry_ms_per_frame"] for b in rows], "k-o", label="parry3d baseline")
    for i, name in enumerate(methods):
        ms = [b["methods"][i]["ms_per_frame"] for b in rows]
        speedup = [b["methods"][i]["speedup_vs_parry"] for b in rows]
        left.plot(gaps, ms, "-o", label=name)
        right.plot(gaps, speedup, "-o", label=name)
    for ax in (left, right):
        ax.invert_xaxis()
        ax.axvline(0.0, color="grey", lw=0.8, ls="--")
        ax.set_xlabel("gap to the wall, cm (negative: deepest penetration)")
        ax.grid(alpha=0.3)
    left.set_ylabel("median ms per frame")
    left.set_ylim(bottom=0)
    right.set_ylabel("speed-up over parry3d (×)")
    right.set_ylim(bottom=0)
    right.axhline(1.0, color="k", lw=0.8)
    left.legend(fontsize=8)
    right.legend(fontsize=8)
    frames = rows[0]["frames"]
    fig.suptitle(
        f"{rows[0]['scenario'].split(',')[0]}: near miss to deep contact "
        f"({rows[0]['vertices']}-vertex character, {frames} frames per gap, {rows[0]['threads']} threads)"
    )
    fig.tight_layout()
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
