"""Outputs written under a temporary name beside their target (PATH.tmp) and renamed into place
when complete, so a killed or failed run never leaves a half-written file that looks complete
(the convention of the C++ side too: model/include/hrpp/util/atomic_file.h)."""
import json
import os
from pathlib import Path


def tmp_path(path) -> Path:
    """The temporary name of PATH: PATH.tmp, in the same directory (so the rename is atomic)."""
    path = Path(path)
    return path.with_name(path.name + ".tmp")


def commit_tmp(path) -> None:
    """Renames PATH.tmp, written completely (by this process or a tool it ran), to PATH. On
    failure the temporary file is removed and the error raised."""
    tmp = tmp_path(path)
    try:
        os.replace(tmp, path)
    except OSError:
        tmp.unlink(missing_ok=True)
        raise


def write_atomic(path, data) -> None:
    """Writes DATA (str or bytes) to PATH through PATH.tmp. On failure the temporary file is
    removed, PATH is left as it was, and the error (naming the file) raised."""
    tmp = tmp_path(path)
    try:
        if isinstance(data, (bytes, bytearray)):
            tmp.write_bytes(data)
        else:
            tmp.write_text(data)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    commit_tmp(path)


def write_json_atomic(path, obj, indent=2, newline=True) -> None:
    """json.dump(obj, indent=indent) to PATH through PATH.tmp (a final newline when asked)."""
    write_atomic(path, json.dumps(obj, indent=indent) + ("\n" if newline else ""))
