"""Debian's python3-* packages (python3-matplotlib, python3-markdown) for the papers/ scripts,
whatever python3 runs them: under another interpreter (pyenv, a venv) that lacks the module,
the script runs itself again with Debian's /usr/bin/python3."""
import importlib
import os
import sys


def require(module, package):
    """The module imported, or the script re-run under /usr/bin/python3, or exit naming the package."""
    try:
        return importlib.import_module(module)
    except ImportError:
        debian = "/usr/bin/python3"
        if os.path.exists(debian) and os.path.realpath(sys.executable) != os.path.realpath(debian):
            os.execv(debian, [debian, *sys.argv])
        sys.exit(f"{module} is missing: apt-get install {package}")
