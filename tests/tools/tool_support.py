"""What the tool tests share: the repository's root, tools/ on the import path (so
that `from voxgi_tools import ...` finds the project's own tools), and how a check
fails: one line, FAIL and what was wrong, and exit status 1."""
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
TOOLS = os.path.join(ROOT, "tools")
if TOOLS not in sys.path:
    sys.path.insert(0, TOOLS)


def fail(msg):
    print(f"FAIL: {msg}")
    sys.exit(1)
