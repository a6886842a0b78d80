"""`ldlpgs view` and `ldlpgs step --html-file` (apps/step_command.cpp): the two write the same
page for the same run; bad input is exit code 2 and one line naming the file and the problem,
and an unwritable page is refused before the run.

python3 view_command_test.py --ldlpgs BIN --work DIR"""
import argparse
import os
import shutil
import subprocess
import sys


def fail(message):
    sys.exit("view_command_test: FAIL: " + message)


def run(ldlpgs, *args):
    return subprocess.run([ldlpgs, *args], capture_output=True, text=True, timeout=120)


def refused(ldlpgs, args, *fragments):
    """ldlpgs ARGS exits 2 with one line on stderr holding every fragment."""
    r = run(ldlpgs, *args)
    lines = r.stderr.splitlines()
    if r.returncode != 2 or len(lines) != 1 or not all(f in r.stderr for f in fragments):
        fail(f"ldlpgs {' '.join(args)}: exit {r.returncode}, stderr {r.stderr!r}; wanted 2 and one line with {fragments}")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--ldlpgs", required=True)
    parser.add_argument("--work", required=True)
    a = parser.parse_args()
    shutil.rmtree(a.work, ignore_errors=True)
    os.makedirs(a.work)

    pages = {}
    for command in ("view", "step"):
        page = os.path.join(a.work, command + ".html")
        r = run(a.ldlpgs, command, "box-stack-1000", "--steps", "30", "--html-file", page)
        if r.returncode != 0 or not os.path.exists(page):
            fail(f"ldlpgs {command} exited {r.returncode}: {r.stderr}")
        if f"viewer page           {page}: " not in r.stdout:
            fail(f"ldlpgs {command} does not name its page: {r.stdout}")
        with open(page, "rb") as f:
            pages[command] = f.read()
    if pages["view"] != pages["step"]:
        fail("view and step --html-file wrote different pages for the same run")
    if not pages["view"].startswith(b"<!doctype html>"):
        fail("the page does not start with <!doctype html>")

    missing = os.path.join(a.work, "no-such-dir", "v.html")
    refused(a.ldlpgs, ["view", "pendulum", "--html-file", missing], missing, "cannot write the HTML file")
    refused(a.ldlpgs, ["view", "pendulum"], "--html-file is required")
    refused(a.ldlpgs, ["view", "no-such-scene", "--html-file", os.path.join(a.work, "x.html")], "no-such-scene")
    if os.path.exists("/dev/full"):
        refused(a.ldlpgs, ["view", "pendulum", "--steps", "3", "--html-file", "/dev/full"], "/dev/full",
                "cannot write the HTML file")
    # An unwritable page is refused before the run: a run of 10^9 steps would take hours.
    refused(a.ldlpgs, ["view", "pendulum", "--steps", "1000000000", "--html-file", missing], missing)
    print("view_command_test: ok")


if __name__ == "__main__":
    main()
