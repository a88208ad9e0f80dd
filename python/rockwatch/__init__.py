"""rockwatch: the rocking engine of the rockwatch command line for Python (docs/python.md).

The compiled extension is the submodule rockwatch.rockwatch (its own name is rockwatch); everything it defines is
re-exported here, so `import rockwatch` reads the same in an installed package and in the build tree
(PYTHONPATH=build/release/python, where the extension is the top-level module).
"""
from .rockwatch import *  # noqa: F401,F403
from .rockwatch import __doc__ as _extension_doc, __version__  # noqa: F401

if _extension_doc:
    __doc__ = _extension_doc
