#!/usr/bin/env python3
"""The plot of `soltex-bench accuracy`: PSNR against frame time, one point per distinct frame,
from the sweep's CSV, with the Pareto front drawn through its points.

    plot_accuracy.py CSV OUT [--clock cpu|wall] [--title TEXT] [--note LINE]...
                     [--per-pixel MS,Q1,Q3,PSNR]

OUT's extension picks the format (.svg, .png, .pdf). soltex-bench runs this after writing the
CSV; it can also be run by hand on docs/accuracy.csv. Exits with 3 when matplotlib is missing.
"""
import argparse
import csv
import sys

try:
    import matplotlib

    matplotlib.use("Agg")  # no display needed
    import matplotlib.pyplot as plt
except ImportError:
    print("plot_accuracy.py: matplotlib is not installed (Debian: python3-matplotlib)",
          file=sys.stderr)
    sys.exit(3)

FRONT, OTHER, PER_PIXEL, BAR = "#c0392b", "#7f8c8d", "#2471a3", "#aab7b8"


def frames(rows, clock):
    """One point per distinct frame: settings that differ in codec alone draw the same frame,
    so they share its error and its times, and are named on the first one's label."""
    column = "cpu_ms" if clock == "cpu" else "frame_ms"
    points = {}
    for row in rows:
        key = (row["psnr_db"], row["ssim"], row["frame_ms"], row["cpu_ms"])
        if key in points:
            points[key]["also"].append(row["codec"])
            continue
        points[key] = {
            "label": row["setting"], "also": [], "front": row["pareto_front"] == "1",
            "ms": float(row[column]), "q1": float(row[column + "_q1"]),
            "q3": float(row[column + "_q3"]), "psnr": float(row["psnr_db"])}
    for p in points.values():
        if p["also"]:
            p["label"] += " (also " + "/".join(p["also"]) + ")"
    return list(points.values())


def draw(ax, points):
    """Quartile bars, the front as a line through its points, and the markers."""
    for p in points:
        ax.errorbar(p["ms"], p["psnr"], xerr=[[p["ms"] - p["q1"]], [p["q3"] - p["ms"]]],
                    color=BAR, capsize=3, linewidth=1, zorder=1)
    front = sorted((p for p in points if p["front"]), key=lambda p: p["ms"])
    ax.plot([p["ms"] for p in front], [p["psnr"] for p in front], color=FRONT, linewidth=2,
            zorder=2)
    for p in points:
        marker, colour, size = {"front": ("o", FRONT, 7), "other": ("o", OTHER, 5),
                                "per_pixel": ("D", PER_PIXEL, 7)}[kind(p)]
        ax.plot(p["ms"], p["psnr"], marker, color=colour, markersize=size,
                markeredgecolor="white", zorder=3)


def kind(p):
    return p.get("kind", "front" if p["front"] else "other")


def label(ax, points, font_size=7.5):
    """A label beside each point, right of it unless it would leave the axes; a label that
    would cover one placed before moves up or down in steps, with a leader line to its point.
    Front points are placed first, so theirs stay closest."""
    to_px = ax.transData.transform
    right_edge = ax.transAxes.transform((1, 0))[0]
    height = font_size * ax.figure.dpi / 72 * 1.25
    placed = []
    for p in sorted(points, key=lambda p: (not p["front"], -p["psnr"])):
        x, y = to_px((p["ms"], p["psnr"]))
        width = 0.55 * font_size * ax.figure.dpi / 72 * len(p["label"])
        right = x + 8 + width < right_edge
        x0 = x + 8 if right else x - 8 - width
        for step in [0, -1, 1, -2, 2, -3, 3, -4, 4, -5, 5, -6, 6]:
            dy = step * height
            box = (x0, y + dy - height / 2, x0 + width, y + dy + height / 2)
            if not any(box[0] < b[2] and b[0] < box[2] and box[1] < b[3] and b[1] < box[3]
                       for b in placed):
                break
        placed.append(box)
        ax.annotate(p["label"], (p["ms"], p["psnr"]), xytext=(8 if right else -8, dy),
                    textcoords="offset pixels", ha="left" if right else "right", va="center",
                    fontsize=font_size, color="#7b241c" if p["front"] else "#4d5656",
                    fontweight="bold" if p["front"] else "normal",
                    arrowprops={"arrowstyle": "-", "color": "#85929e", "linewidth": 0.6}
                    if step else None)


def crowd(points):
    """The points close in time to the median frame, when others stretch the time axis so far
    that these would sit on top of each other: they get a magnified inset."""
    times = sorted(p["ms"] for p in points)
    median = times[len(times) // 2]
    close = [p for p in points if p["ms"] <= 1.25 * median]
    spread = max(p["ms"] for p in close) - min(p["ms"] for p in close)
    return close if len(close) >= 3 and times[-1] - times[0] > 4 * spread else []


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("csv")
    parser.add_argument("out")
    parser.add_argument("--clock", choices=["cpu", "wall"], default="cpu")
    parser.add_argument("--title", default="What accuracy costs")
    parser.add_argument("--note", action="append", default=[])
    parser.add_argument("--per-pixel", help="MS,Q1,Q3,PSNR of per-pixel evaluation, for scale")
    args = parser.parse_args()

    with open(args.csv, newline="") as f:
        points = frames(list(csv.DictReader(f)), args.clock)
    if not points:
        sys.exit(f"plot_accuracy.py: {args.csv} has no settings")
    if args.per_pixel:
        ms, q1, q3, psnr = (float(v) for v in args.per_pixel.split(","))
        points.append({"label": "per-pixel evaluation, no cache", "front": False, "ms": ms,
                       "q1": q1, "q3": q3, "psnr": psnr, "kind": "per_pixel"})

    plt.rcParams["svg.hashsalt"] = "soltex"  # the same CSV gives the same SVG
    zoomed = crowd(points)
    if zoomed:
        fig, (ax, zoom) = plt.subplots(1, 2, figsize=(13, 6.6), width_ratios=[1, 1.6])
    else:
        fig, ax = plt.subplots(figsize=(9.6, 6.6))
    fig.subplots_adjust(left=0.06 if zoomed else 0.08, right=0.98, top=0.85, bottom=0.17,
                        wspace=0.12)
    axes = [(ax, points, [p for p in points if p not in zoomed])]
    if zoomed:
        axes.append((zoom, zoomed, zoomed))
        zoom.set_title("magnified: the settings within a quarter of the median frame time",
                       fontsize=8, color="#5d6d7e")
    unit = "CPU" if args.clock == "cpu" else "wall"
    for a, shown, labelled in axes:
        draw(a, shown)
        a.margins(x=0.12, y=0.06)
        a.autoscale_view()
        a.grid(color="#eaeded")
        a.tick_params(labelsize=8)
        a.set_xlabel(f"{unit} time per warm frame, ms (left is faster)", fontsize=9)
        label(a, labelled)
    ax.set_ylabel("PSNR, dB (up is more accurate)", fontsize=9)
    if zoomed:  # the magnified range, outlined on the whole
        lo_x, hi_x = zoom.get_xlim()
        lo_y, hi_y = zoom.get_ylim()
        ax.add_patch(plt.Rectangle((lo_x, lo_y), hi_x - lo_x, hi_y - lo_y, fill=False,
                                   edgecolor="#5d6d7e", linestyle="--", linewidth=0.8))
    clock = "CPU time, every render thread summed" if args.clock == "cpu" else "wall time"
    fig.suptitle("\n".join([args.title] + args.note +
                            [f"Frame time: median of warm frames ({clock}), bars from first to "
                             "third quartile."]), x=0.06, ha="left", fontsize=9)
    fig.legend(handles=[
        plt.Line2D([], [], color=FRONT, marker="o", linewidth=2,
                   label="Pareto front: nothing else is both faster and more accurate"),
        plt.Line2D([], [], color=OTHER, marker="o", linestyle="", label="other settings"),
        plt.Line2D([], [], color=PER_PIXEL, marker="D", linestyle="", label="no cache, for scale")],
        loc="lower left", bbox_to_anchor=(0.06, 0.0), ncols=3, fontsize=8, frameon=False)
    fig.savefig(args.out, metadata={"Date": None} if args.out.endswith(".svg") else None)


if __name__ == "__main__":
    main()
