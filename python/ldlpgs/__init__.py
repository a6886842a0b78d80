# The ldlpgs package: the bindings (the extension ldlpgs._ldlpgs, python/*.cpp) under the names
# they had when the module was the extension alone (ldlpgs.order, ldlpgs.InputError, ...), and
# ldlpgs.study (study.py), imported on demand: it needs pandas, the bindings do not.
from ._ldlpgs import *  # noqa: F401,F403 (every binding, as `import ldlpgs` gave them)
from ._ldlpgs import __doc__, __version__  # noqa: F401

# The classes, exceptions and functions report themselves as ldlpgs.X, as before: in messages,
# reprs, help() and pickles (a pickled ldlpgs.InputError is found again by that name).
for _value in list(globals().values()):
    if getattr(_value, "__module__", None) == "ldlpgs._ldlpgs":
        try:
            _value.__module__ = __name__
        except (AttributeError, TypeError):  # a type that does not let its module be set
            pass
del _value
