#!/usr/bin/env python3
"""Writes the book's measured figures: runs `gnomon compare` over the demo's named views and
puts its "Over all views" table into docs/src/results.md, and each technique's row into its
page, between `<!-- figures:NAME -->` and `<!-- /figures -->` markers.

Usage: scripts/book-figures.py [GNOMON] (default target/release/gnomon; build it first).
"""
import re
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
COMMAND = ["compare", "--techniques", "all", "--size", "640x360", "--shadow-map", "2048"]
# A page's figures: the rows of the table it shows.
PAGES = {
    "uniform": ["uniform"], "focused": ["focused"], "lispsm": ["lispsm"], "tsm": ["tsm"],
    "xpsm": ["xpsm"], "psm": ["psm"], "sppsm": ["sppsm", "sppsm-same-texels"],
    "cascades": ["cascades", "cascades-stable", "cascades-lispsm", "cascades-best"],
    "cube": ["cube"], "paraboloid": ["paraboloid", "paraboloid-cube-texels"],
}


def replace_between(text, name, body):
    pattern = re.compile(rf"(<!-- figures:{name} -->\n).*?(<!-- /figures -->)", re.S)
    if not pattern.search(text):
        raise SystemExit(f"book-figures: no <!-- figures:{name} --> marker")
    return pattern.sub(lambda m: m.group(1) + body + m.group(2), text)


def main():
    gnomon = sys.argv[1] if len(sys.argv) > 1 else str(ROOT / "target/release/gnomon")
    with tempfile.TemporaryDirectory() as out:
        subprocess.run([gnomon, *COMMAND, "--out", out], check=True, stdout=subprocess.DEVNULL)
        report = Path(out, "index.md").read_text()
    device = re.search(r"rendered on ([^.\n]*)", report)
    table = report.split("## Over all views", 1)[1].strip().split("\n\n")[0]
    rows = {line.split("|")[1].strip(): line for line in table.splitlines()[2:]}
    head = "\n".join(table.splitlines()[:2])
    command = "gnomon " + " ".join(COMMAND)
    where = f" on {device.group(1)}" if device else ""
    results = ROOT / "docs/src/results.md"
    results.write_text(replace_between(
        results.read_text(), "demo",
        f"Wrong pixels against the exact volumes over the demo's ten named views (the pixels "
        f"facing the light), 640x360 with 2048 maps{where} (`{command}`; "
        f"`scripts/book-figures.py` writes this table and the techniques' figures):\n\n"
        f"{table}\n\n"))
    for page, names in PAGES.items():
        path = ROOT / f"docs/src/techniques/{page}.md"
        lines = "\n".join(rows[n] for n in names if n in rows)
        path.write_text(replace_between(
            path.read_text(), page,
            f"Over the demo's named views, 640x360 with 2048 maps (`{command}`):\n\n"
            f"{head}\n{lines}\n\n"))
    print("book-figures: wrote docs/src/results.md and the technique pages")


if __name__ == "__main__":
    main()
