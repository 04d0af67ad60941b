#!/usr/bin/env python3
"""Checks the relative links of the project's Markdown pages: every linked file exists and every #anchor names a
heading of its page (GitHub's rule: lower case, punctuation other than '-' and '_' dropped, spaces to '-').
Prints one line per broken link (page:line: target) and exits 1 if there is any.
Usage: tests/tools/check_doc_links.py [ROOT]"""
import pathlib
import re
import sys

LINK = re.compile(r"\]\(([^)\s]+)\)")
FENCE = re.compile(r"^\s*(```|~~~)")


def anchors(page: pathlib.Path) -> set:
    found, counts, fenced = set(), {}, False
    for line in page.read_text(encoding="utf-8").splitlines():
        if FENCE.match(line):
            fenced = not fenced
        if fenced or not line.startswith("#"):
            continue
        text = line.lstrip("#").strip().lower()
        slug = re.sub(r"[^\w\- ]", "", text).replace(" ", "-")
        n = counts.get(slug, 0)
        counts[slug] = n + 1
        found.add(slug if n == 0 else f"{slug}-{n}")
    return found


def main() -> int:
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".").resolve()
    pages = [p for p in root.glob("*.md")] + list((root / "docs").glob("*.md"))
    pages += list((root / "bench" / "results").rglob("*.md"))
    cache, broken = {}, 0
    for page in pages:
        for number, line in enumerate(page.read_text(encoding="utf-8").splitlines(), 1):
            for target in LINK.findall(line):
                if re.match(r"^[a-z]+:", target):
                    continue  # http:, https:, mailto:
                path, _, anchor = target.partition("#")
                linked = (page.parent / path).resolve() if path else page
                if not linked.exists():
                    print(f"{page.relative_to(root)}:{number}: {target} (no such file)")
                    broken += 1
                    continue
                if anchor and linked.suffix == ".md":
                    if linked not in cache:
                        cache[linked] = anchors(linked)
                    if anchor not in cache[linked]:
                        print(f"{page.relative_to(root)}:{number}: {target} (no such heading)")
                        broken += 1
    return 1 if broken else 0


if __name__ == "__main__":
    sys.exit(main())
