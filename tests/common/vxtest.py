"""The Python tests' shared harness: named checks that print "ok"/"FAIL" and
count into the exit status, and voxkit's tools run by name from BIN_DIR.

    check = Checks()
    tool = tools(BIN)
    check(tool("svo_info", path) != b"", "svo_info prints something")
    check.exit()   # prints the failure count, exits 1 on any failure
"""
import os
import subprocess
import sys


class Checks:
    def __init__(self):
        self.failures = []

    def __call__(self, cond, what):
        print(("ok    " if cond else "FAIL  ") + what)
        if not cond:
            self.failures.append(what)
        return bool(cond)

    def exit(self):
        print(f"{len(self.failures)} failures")
        sys.exit(1 if self.failures else 0)


def tools(bin_dir):
    """a function tool(name, *args) -> stdout bytes; a failing tool raises"""
    def tool(name, *args):
        return subprocess.run([os.path.join(bin_dir, name), *args], check=True, capture_output=True).stdout
    return tool
