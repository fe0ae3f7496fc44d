#!/usr/bin/env python3
"""Every relative link of README.md, docs/*.md, sitl/README.md and domains/README.md points at a file that
exists (and, with a #fragment, at a heading of it). Prints each broken link as file:line and exits 1."""
import pathlib
import re
import sys

root = pathlib.Path(__file__).resolve().parent.parent
pages = [root / "README.md", root / "sitl/README.md", root / "domains/README.md"]
pages += sorted((root / "docs").glob("*.md"))
link = re.compile(r"\]\(([^)\s]+)\)")


def anchors(path):
    out = set()
    for line in path.read_text(encoding="utf-8").splitlines():
        if line.startswith("#"):
            text = line.lstrip("#").strip().lower()
            text = re.sub(r"[^\w\- ]", "", text).replace(" ", "-")
            out.add(text)
    return out


broken = []
for page in pages:
    if not page.exists():
        continue
    in_code = False
    for n, line in enumerate(page.read_text(encoding="utf-8").splitlines(), 1):
        if line.startswith("```"):
            in_code = not in_code
        if in_code:
            continue
        for target in link.findall(line):
            if re.match(r"^[a-z]+:", target):
                continue
            path, _, frag = target.partition("#")
            dest = (page.parent / path).resolve() if path else page
            if not dest.exists():
                broken.append(f"{page.relative_to(root)}:{n}: {target} (no such file)")
            elif frag and dest.suffix == ".md" and frag not in anchors(dest):
                broken.append(f"{page.relative_to(root)}:{n}: {target} (no such heading)")
for b in broken:
    print(b)
print(f"doc links: {len(broken)} broken" if broken else "doc links: ok")
sys.exit(1 if broken else 0)
