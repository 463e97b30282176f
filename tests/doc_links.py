#!/usr/bin/env python3
"""doc_links.py SRC - every relative link of the Markdown a user reads
(README.md, docs/**.md, lcmtypes/PROTOCOL.md, docs/study/**) names a file or
directory that exists (docs/daemon.md linked ../systemd/wormgeard.service,
which is generated at install time, not in the tree). Anchors (#...) and
URLs with a scheme are not checked. Exit 1 naming each broken link."""
import os
import re
import sys

src = sys.argv[1]
files = [os.path.join(src, "README.md"), os.path.join(src, "lcmtypes", "PROTOCOL.md")]
for root, _, names in os.walk(os.path.join(src, "docs")):
    files += [os.path.join(root, n) for n in names if n.endswith(".md")]
link = re.compile(r"\]\(([^)\s]+)\)")
bad = checked = 0
for f in files:
    text = open(f, encoding="utf-8").read()
    for m in link.finditer(text):
        target = m.group(1).split("#", 1)[0]
        if not target or re.match(r"^[a-z][a-z0-9+.-]*:", target):
            continue
        checked += 1
        path = os.path.normpath(os.path.join(os.path.dirname(f), target))
        if not os.path.exists(path):
            line = text.count("\n", 0, m.start()) + 1
            print(f"{os.path.relpath(f, src)}:{line}: broken link {m.group(1)}")
            bad += 1
print(f"{checked} relative links in {len(files)} files, {bad} broken")
sys.exit(1 if bad or checked < 20 else 0)
