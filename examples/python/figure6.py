"""The LiSPSM paper's Figure 6: perspective aliasing dp/ds along the view axis of a uniform
map, a perspective shadow map and a light space perspective shadow map, with the logarithmic
limit no single map can beat, measured from gnomon's actual matrices (Wimmer, Scherzer and
Purgathofer, "Light Space Perspective Shadow Maps", 2004).

    python examples/python/figure6.py [OUT.png] [--gamma DEG]

Needs `pip install ./crates/gnomon-py matplotlib`.
"""

import argparse
import sys

import gnomon

CURVES = [
    ("uniform", "uniform shadow map", "tab:gray"),
    ("psm-paper", "perspective shadow map (n = z_n)", "tab:red"),
    ("lispsm", "LiSPSM (n_opt)", "tab:blue"),
]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", nargs="?", default="figure6.png", help="the PNG to write")
    parser.add_argument("--gamma", type=float, default=90.0, help="view-light angle, degrees")
    parser.add_argument("--zn", type=float, default=1.0)
    parser.add_argument("--zf", type=float, default=100.0)
    args = parser.parse_args()
    if not args.out.endswith(".png"):
        print(f"error: {args.out}: the figure is written as PNG (name it *.png)", file=sys.stderr)
        sys.exit(2)
    try:
        analysis = gnomon.analyze(zn=args.zn, zf=args.zf, gamma=args.gamma)
    except gnomon.GnomonError as e:
        print(f"error: {e}", file=sys.stderr)
        sys.exit(2)

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4.5))
    for name, label, colour in CURVES:
        z, dp_ds = analysis.curve(name)
        ax.plot(z, dp_ds, label=f"{label}: max {dp_ds.max():.1f}", color=colour)
    ax.axhline(analysis.logarithmic_ideal, color="black", linestyle="--",
               label=f"logarithmic limit z_n ln(z_f / z_n) = {analysis.logarithmic_ideal:.2f}")
    ax.set_yscale("log")
    ax.set_xlabel("view distance z")
    ax.set_ylabel("dp/ds")
    ax.set_title(f"Perspective aliasing, z_n = {analysis.z_n:g}, z_f = {analysis.z_f:g}, "
                 f"gamma = {analysis.gamma:g} degrees")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(args.out, dpi=120)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
