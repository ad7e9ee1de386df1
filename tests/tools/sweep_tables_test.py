#!/usr/bin/env python3
"""The documents' study tables are generated from the committed CSVs: regenerating
every sweep-table block (`tools/sweep tables --check`) must reproduce what is
committed, and a hand edit inside a block must be caught (exit 1, naming the
block) and undone by `tools/sweep tables`."""
import os
import re
import shutil
import subprocess
import sys
import tempfile

from tool_support import ROOT, fail
SWEEP = [sys.executable, "-m", "voxgi_tools", "sweep", "tables"]
# The tables need no package from the venv: the system's python runs them.
os.environ["PYTHONPATH"] = os.path.join(ROOT, "tools")
DOCS = ["README.md", "docs/study.md", "docs/measurements.md"]


def main():
    p = subprocess.run(SWEEP + ["--check"], capture_output=True, text=True)
    print(p.stdout + p.stderr)
    if p.returncode != 0:
        fail("the committed tables differ from their CSVs: run tools/sweep tables")
    blocks = 0
    for doc in DOCS:
        with open(os.path.join(ROOT, doc)) as f:
            blocks += len(re.findall(r"^<!-- begin sweep-table \S+ from \S+ -->$", f.read(),
                                     re.M))
    if not re.search(rf"sweep tables: {blocks} tables, 0 differ", p.stdout) or blocks < 2:
        fail(f"expected all {blocks} blocks checked")

    with tempfile.TemporaryDirectory(prefix="voxgi-sweep-tables-") as tmp:
        doc = os.path.join(tmp, "study.md")
        shutil.copy(os.path.join(ROOT, "docs", "study.md"), doc)
        with open(doc) as f:
            text = f.read()
        m = re.search(r"<!-- begin sweep-table (\S+) from \S+ -->\n\n\|.*\n\|.*\n\| (\S+) \|",
                      text)
        if not m:
            fail("docs/study.md has no generated table")
        edited = text[:m.start(2)] + "999" + text[m.end(2):]
        with open(doc, "w") as f:
            f.write(edited)
        p = subprocess.run(SWEEP + ["--check", doc], capture_output=True, text=True)
        print(p.stdout + p.stderr)
        if p.returncode != 1 or m.group(1) not in p.stdout:
            fail(f"a hand edit in {m.group(1)} was not caught (exit {p.returncode})")
        subprocess.run(SWEEP + [doc], check=True, capture_output=True)
        with open(doc) as f:
            if f.read() != text:
                fail("tools/sweep tables did not restore the edited block")
    print("PASS")


if __name__ == "__main__":
    main()
