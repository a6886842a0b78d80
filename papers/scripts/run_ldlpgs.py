"""The papers/ scripts run the program through this: its standard output, or exit with its message."""
import subprocess
import sys


def run(program, *args):
    out = subprocess.run([program, *args], capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit(f"ldlpgs {' '.join(args)}: {out.stderr.strip()}")
    return out.stdout
