"""Running the project's tools from the scripts: a tool that writes a JSON report (e.g.
`hrpp predict ... --json PATH`), run to completion and its report read back."""
import json
import subprocess
from pathlib import Path


class ToolFailed(RuntimeError):
    """A tool exited non-zero: its command, exit code and standard error."""

    def __init__(self, cmd: list[str], returncode: int, stderr: str):
        self.cmd, self.returncode, self.stderr = list(cmd), returncode, stderr
        super().__init__(f"{' '.join(self.cmd)} exited {returncode}:\n{stderr}")


def run_json(cmd: list[str], json_path):
    """Runs CMD (output captured) and returns the JSON it wrote to JSON_PATH. Raises ToolFailed
    when it exits non-zero."""
    proc = subprocess.run([str(c) for c in cmd], capture_output=True, text=True)
    if proc.returncode != 0:
        raise ToolFailed([str(c) for c in cmd], proc.returncode, proc.stderr)
    return json.loads(Path(json_path).read_text())
