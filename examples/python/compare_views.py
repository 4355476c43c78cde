"""One view rendered with three shadow-map techniques and the exact shadow volumes: each
technique's shadow mask, where it differs from the exact one, and its undersampling (pixels
per texel), side by side.

    python examples/python/compare_views.py [OUT.png] [--view NAME] [--size WxH]
        [--techniques focused,lispsm,cascades] [--scene-file F]

Needs `pip install ./crates/gnomon-py matplotlib` and a GPU driver (Mesa's lavapipe will do).
"""

import argparse
import sys

import numpy as np

import gnomon


def parse_args():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", nargs="?", default="compare_views.png", help="the PNG to write")
    parser.add_argument("--view", default="street", help="a named view of the scene")
    parser.add_argument("--size", default="480x270", help="image size WxH")
    parser.add_argument("--techniques", default="focused,lispsm,cascades")
    parser.add_argument("--scene-file", help="a scene file (default: the demo scene)")
    parser.add_argument("--resolution", type=int, default=2048, help="shadow-map texels")
    args = parser.parse_args()
    if not args.out.endswith(".png"):
        fail(f"{args.out}: the figure is written as PNG (name it *.png)")
    try:
        args.size = tuple(int(v) for v in args.size.lower().split("x"))
        assert len(args.size) == 2
    except (ValueError, AssertionError):
        fail(f"--size {args.size}: give WxH, such as 480x270")
    args.techniques = [t.strip() for t in args.techniques.split(",") if t.strip()]
    return args


def fail(message):
    print(f"error: {message}", file=sys.stderr)
    sys.exit(2)


def main():
    args = parse_args()
    try:
        scene = gnomon.Scene.load(args.scene_file) if args.scene_file else gnomon.Scene.demo()
        camera, light = scene.view(args.view, aspect=args.size[0] / args.size[1])
        exact = gnomon.render(scene, camera, light, technique="volumes", size=args.size)
        frames = [
            gnomon.render(scene, camera, light, technique=t, size=args.size, resolution=args.resolution)
            for t in args.techniques
        ]
    except gnomon.GnomonError as e:
        fail(e)

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    surface = exact.mask != 128
    fig, axes = plt.subplots(3, len(frames), figsize=(4 * len(frames), 7.5), squeeze=False, layout="constrained")
    for column, (name, frame) in enumerate(zip(args.techniques, frames)):
        wrong = (frame.mask != exact.mask) & surface
        share = 100 * wrong.sum() / max(surface.sum(), 1)
        axes[0][column].imshow(frame.mask, cmap="gray", vmin=0, vmax=255)
        axes[0][column].set_title(f"{name}: mask")
        # Wrong pixels in red over the exact mask.
        overlay = np.stack([exact.mask] * 3, axis=-1) // 2
        overlay[wrong] = [255, 0, 0]
        axes[1][column].imshow(overlay)
        axes[1][column].set_title(f"wrong (red): {share:.3f}%")
        error = np.where(surface, np.clip(frame.error_map, 1e-2, 1e2), np.nan)
        shown = axes[2][column].imshow(np.log10(error), cmap="magma", vmin=-2, vmax=2)
        p95 = np.percentile(frame.error_map[surface & (frame.error_map > 0)], 95)
        axes[2][column].set_title(f"log10 pixels/texel, p95 {p95:.2f}")
    for ax in axes.flat:
        ax.set_axis_off()
    fig.colorbar(shown, ax=axes[2].tolist(), shrink=0.8)
    fig.suptitle(f"{scene.name}, view {args.view}, {args.size[0]}x{args.size[1]}, on {exact.device}")
    fig.savefig(args.out, dpi=100)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
