#!/usr/bin/env python3
"""Checks every relative link and anchor in a built mdBook (mdBook 0.5 has no link check of
its own): each href that is not absolute must name a file of the book, and a #fragment an id
in that file. Prints one line per broken link and exits 1 if there is any.

Usage: scripts/check-links.py docs/book [FILE.md ...]: also checks that every relative link
of each Markdown file (the README) names a file of the repository.
"""
import re
import sys
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import unquote, urlsplit


class Page(HTMLParser):
    def __init__(self):
        super().__init__()
        self.ids, self.links = set(), []

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        if "id" in attrs:
            self.ids.add(attrs["id"])
        if tag == "a" and attrs.get("name"):
            self.ids.add(attrs["name"])
        for key in ("href", "src"):
            if key in attrs and attrs[key] is not None:
                self.links.append(attrs[key])


def parse(path, cache={}):
    if path not in cache:
        page = Page()
        page.feed(path.read_text(encoding="utf-8", errors="replace"))
        cache[path] = page
    return cache[path]


def main(root):
    root = Path(root).resolve()
    broken = 0
    pages = sorted(root.rglob("*.html"))
    if not pages:
        print(f"check-links: no HTML under {root}")
        return 1
    for page_path in pages:
        # The theme's own pages (print, 404) link to themselves through the site root.
        if page_path.name in ("404.html", "toc.html"):
            continue
        for link in dict.fromkeys(parse(page_path).links):
            parts = urlsplit(link)
            if parts.scheme or link.startswith("//") or link.startswith("mailto:"):
                continue
            target = page_path if not parts.path else (page_path.parent / unquote(parts.path))
            target = target.resolve()
            if target.is_dir():
                target = target / "index.html"
            if not target.exists():
                print(f"{page_path.relative_to(root)}: broken link {link}")
                broken += 1
                continue
            if parts.fragment and target.suffix == ".html":
                if unquote(parts.fragment) not in parse(target).ids:
                    print(f"{page_path.relative_to(root)}: no anchor #{parts.fragment} in "
                          f"{target.relative_to(root)}")
                    broken += 1
    print(f"check-links: {len(pages)} pages, {broken} broken links")
    return 1 if broken else 0


def check_markdown(path):
    """Relative links of a Markdown file, outside code blocks: each must name a file."""
    path = Path(path)
    text = re.sub(r"```.*?```", "", path.read_text(encoding="utf-8"), flags=re.S)
    broken = 0
    for link in re.findall(r"\]\(([^)\s]+)\)", text):
        parts = urlsplit(link)
        if parts.scheme or link.startswith("#"):
            continue
        if not (path.parent / unquote(parts.path)).exists():
            print(f"{path}: broken link {link}")
            broken += 1
    return broken


if __name__ == "__main__":
    book = sys.argv[1] if len(sys.argv) > 1 else "docs/book"
    failed = main(book)
    markdown_broken = sum(check_markdown(md) for md in sys.argv[2:])
    if markdown_broken:
        print(f"check-links: {markdown_broken} broken links in Markdown files")
    sys.exit(1 if failed or markdown_broken else 0)
