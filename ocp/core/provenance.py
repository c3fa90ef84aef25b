"""Where a result comes from: the commit of the code that computed it."""

import subprocess
from pathlib import Path


def git_commit():
    """HEAD of the checkout ocp runs from, with "+dirty" when its code (ocp/, the data written into
    it excepted) differs from it; None outside a git checkout (an installed wheel)."""
    root = Path(__file__).resolve().parents[2]
    try:
        head = subprocess.run(["git", "-C", root, "rev-parse", "HEAD"], capture_output=True, text=True, check=True)
        dirty = subprocess.run(["git", "-C", root, "status", "--porcelain", "--untracked-files=no", "--", "ocp",
                                ":(exclude)ocp/synthesis/data"],
                               capture_output=True, text=True, check=True)
    except (OSError, subprocess.CalledProcessError):
        return None
    return head.stdout.strip() + ("+dirty" if dirty.stdout.strip() else "")
