"""Running the project's tools from the scripts: a tool that writes a JSON report (e.g.
`hrpp predict ... --json PATH`), run to completion and its report read back; a study run's files
made to name their destinations (restore_paths)."""
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


def restore_paths(task, result) -> None:
    """Rewrites the files of a finished study run (pyhrpp/study.py: TASK and its RESULT) so that
    they name their destinations (Task.files) where the tool wrote the worker's temporary files:
    hrpp's reports record their own command line (`tool.command_line`), in which the worker's
    `{NAME}` paths stand. Files that do not name them are left as the driver wrote them."""
    from pyhrpp.files import write_atomic
    temp = {}  # NAME -> the path the worker gave the tool
    for template, actual in zip(task.cmd, result.data.get("cmd") or []):
        template = str(template)
        for name, dest in task.files.items():
            tag = "{" + name + "}"
            if dest and tag in template:
                before, after = template.split(tag, 1)
                if actual.startswith(before) and actual.endswith(after):
                    temp[name] = actual[len(before):len(actual) - len(after)]
    for name, dest in task.files.items():
        text = result.files.get(name)
        if not dest or text is None:
            continue
        new = text
        for n, path in temp.items():
            new = new.replace(path, str(task.files[n]))
        if new != text:
            result.files[name] = new
            write_atomic(dest, new)
