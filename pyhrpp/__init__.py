"""Helpers shared by the project's Python scripts (model/tools, rtl/syn, tb, fuzz, scenes,
model/test). Scripts run with the system python3 and with the venv's, so none installs this
package: each puts the repository root on sys.path from its own location, e.g.

    sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2]))
    from pyhrpp.files import write_atomic

Standard library only.
"""
