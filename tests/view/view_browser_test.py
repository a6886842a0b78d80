"""The viewer's page in a real browser: `ldlpgs view tracked-vehicle` writes it, headless Chromium
(software WebGL, SwiftShader) opens it at two times of the run, #t=0.2 and #t=1.5, and takes a
screenshot of each. Fails on any error the page saw (its check line, view/viewer.html), on any
other line on the browser's console, on a 3D view or plot that stays the background colour in the
screenshot (or the 3D view that has none of it: never rendered), and when the two times draw the
same 3D view.

python3 view_browser_test.py --ldlpgs BIN --chromium CHROMIUM --work DIR"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "papers", "scripts"))
from debian_python import require  # noqa: E402  (re-runs under Debian's python3 for python3-pil)

Image = require("PIL.Image", "python3-pil")

TIMES = ("0.2", "1.5")
WINDOW = (960, 600)


def fail(message):
    sys.exit("view_browser_test: FAIL: " + message)


def screenshot(chromium, page, t, png, profile):
    """Chromium's console lines for page#t=T, with its screenshot in png. WebGL without a GPU:
    SwiftShader through ANGLE (without --enable-unsafe-swiftshader Chromium falls back to it
    with a deprecation warning on the console)."""
    command = [chromium, "--headless", "--disable-gpu", "--no-sandbox", "--use-angle=swiftshader",
               "--enable-unsafe-swiftshader", f"--user-data-dir={profile}", "--no-first-run",
               "--enable-logging=stderr", "--virtual-time-budget=3000",
               "--hide-scrollbars", f"--window-size={WINDOW[0]},{WINDOW[1]}", f"--screenshot={png}",
               f"file://{page}#t={t}"]
    run = subprocess.run(command, capture_output=True, text=True, timeout=90)
    if run.returncode != 0 or not os.path.exists(png):
        fail(f"chromium exited {run.returncode} without a screenshot at t={t}:\n{run.stderr[-2000:]}")
    return [line for line in run.stderr.splitlines() if ":CONSOLE" in line]


def box(check, name):
    """The x, y, width, height the check line gives for `name` (CSS pixels, the screenshot's)."""
    found = re.search(name + r"=(\d+),(\d+),(\d+),(\d+)", check)
    if not found:
        fail(f"no {name}= in the check line: {check}")
    x, y, w, h = map(int, found.groups())
    return (x, y, x + w, y + h)


def differing(image, colour, tolerance=12):
    """How many pixels of `image` differ from `colour` by more than `tolerance` (summed over RGB)."""
    return sum(1 for p in image.getdata() if sum(abs(a - b) for a, b in zip(p[:3], colour)) > tolerance)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--ldlpgs", required=True)
    parser.add_argument("--chromium", required=True)
    parser.add_argument("--work", required=True)
    a = parser.parse_args()
    if not shutil.which(a.chromium):
        fail(f"chromium not found ({a.chromium}): apt-get install chromium")
    started = time.monotonic()
    shutil.rmtree(a.work, ignore_errors=True)
    os.makedirs(a.work)
    page = os.path.join(a.work, "tracked-vehicle.html")
    run = subprocess.run([a.ldlpgs, "view", "tracked-vehicle", "--steps", "200", "--html-file", page],
                         capture_output=True, text=True, timeout=300)
    if run.returncode != 0:
        fail(f"ldlpgs view exited {run.returncode}: {run.stderr}")

    views = {}
    for t in TIMES:
        png = os.path.join(a.work, f"t{t}.png")
        console = screenshot(a.chromium, page, t, png, os.path.join(a.work, "profile"))
        checks = [line for line in console if "ldlpgs-view check:" in line]
        # Every other console line is a failure (Chromium logs every level as INFO:CONSOLE), but
        # for SwiftShader's performance note on the check's readPixels.
        others = [line for line in console if line not in checks and "GPU stall due to ReadPixels" not in line]
        if others:
            fail(f"t={t}: the console says: {others[0]}")
        if len(checks) != 1 or "ldlpgs-view check: ok" not in checks[0]:
            fail(f"t={t}: the page's check did not pass: {checks or console or 'no console output'}")
        check = checks[0]
        background = tuple(int(x) for x in re.search(r"background=(\d+),(\d+),(\d+)", check).groups())
        image = Image.open(png).convert("RGB")
        if image.size != WINDOW:
            fail(f"t={t}: the screenshot is {image.size}, not {WINDOW}")
        scene = image.crop(box(check, "canvas"))
        drawn = differing(scene, background)
        if drawn < 0.002 * scene.width * scene.height:
            fail(f"t={t}: the 3D view is the background colour {background} in the screenshot ({drawn} pixels)")
        if drawn > 0.95 * scene.width * scene.height:
            fail(f"t={t}: the 3D view has no background colour {background} in the screenshot: never rendered?")
        plot = image.crop(box(check, "plot"))
        if differing(plot, (255, 255, 255)) < 0.01 * plot.width * plot.height:
            fail(f"t={t}: the plot is blank")
        views[t] = scene
        verdict = check.split("ldlpgs-view check: ")[1].split('"')[0]
        print(f"t={t}: {verdict}; {drawn} pixels drawn in the screenshot")

    a_view, b_view = (views[t] for t in TIMES)
    changed = sum(1 for p, q in zip(a_view.getdata(), b_view.getdata()) if p != q)
    if changed < 0.001 * a_view.width * a_view.height:
        fail(f"t={TIMES[0]} and t={TIMES[1]} draw the same 3D view ({changed} pixels differ)")
    print(f"{changed} pixels differ between t={TIMES[0]} and t={TIMES[1]}; {time.monotonic() - started:.1f} s")


if __name__ == "__main__":
    main()
