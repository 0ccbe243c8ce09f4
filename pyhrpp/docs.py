"""Generated blocks of the docs: the text between `<!-- BEGIN name -->` and `<!-- END name -->`
in a Markdown file (docs/results.md), rewritten by the script that makes the figures."""
from pathlib import Path

from .files import write_atomic


def markers(name: str) -> tuple[str, str]:
    return f"<!-- BEGIN {name} -->", f"<!-- END {name} -->"


def replace_block(text: str, name: str, body: str, heading: str | None = None) -> str:
    """TEXT with block NAME's content replaced by BODY (one newline after BEGIN, one before
    END). A block not in TEXT is appended at the end, under HEADING when given."""
    begin, end = markers(name)
    body = body.rstrip("\n")
    if begin in text and end in text:
        head, rest = text.split(begin, 1)
        _, tail = rest.split(end, 1)
        return f"{head}{begin}\n{body}\n{end}{tail}"
    under = f"{heading}\n\n" if heading else ""
    return text.rstrip("\n") + f"\n\n{under}{begin}\n{body}\n{end}\n"


def update_blocks(doc, blocks: dict, headings: dict | None = None, default_text: str = "") -> None:
    """Replaces the blocks (name -> body) in the file DOC (DEFAULT_TEXT when it does not exist)
    and writes it back atomically. headings: name -> heading of a block that must be appended."""
    doc = Path(doc)
    text = doc.read_text() if doc.exists() else default_text
    for name, body in blocks.items():
        text = replace_block(text, name, body, (headings or {}).get(name))
    write_atomic(doc, text)
