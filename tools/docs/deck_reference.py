"""Generate the card section of docs/deck-reference.md from the card structs' doc comments
(and those of the functions that read one card as another's struct, e.g. EIGR as EIGRL).

Every card struct in src/deck/cards/*.rs carries its field table in its doc comment (the one
source of truth). This script collects them, in the order of the PARSERS table, and writes
them between the markers `<!-- deck-reference:start -->` and `<!-- deck-reference:end -->` of
docs/deck-reference.md. `--check` exits 1 when that page is not current (used by the test
suite, tests/readme_reference.rs).
"""
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
CARDS = ROOT / "src" / "deck" / "cards"
PAGE = ROOT / "docs" / "deck-reference.md"
START, END = "<!-- deck-reference:start -->", "<!-- deck-reference:end -->"


def doc_blocks():
    """(title line, body) of every struct doc comment whose first line names a card."""
    blocks = []
    for path in sorted(CARDS.glob("*.rs")):
        lines = path.read_text().splitlines()
        doc = []
        for line in lines:
            s = line.strip()
            if s.startswith("///"):
                doc.append(s[3:].removeprefix(" "))
            elif s.startswith("#["):
                continue
            else:
                card_item = s.startswith("pub struct") or s.startswith("pub fn")
                if doc and card_item and doc[0].startswith("`"):
                    blocks.append((doc[0], "\n".join(doc[1:]).strip()))
                doc = []
    return blocks


def parser_order():
    text = (CARDS / "mod.rs").read_text()
    return re.findall(r'\("([A-Z0-9]+)", \|', text)


def render():
    blocks = doc_blocks()
    order = parser_order()

    def rank(block):
        names = re.findall(r"`([A-Z0-9]+)`", block[0].split("—")[0])
        return min((order.index(n) for n in names if n in order), default=len(order))

    out = []
    for title, body in sorted(blocks, key=rank):
        out.append(f"#### {title}\n\n{body}\n")
    return "\n".join(out)


def main():
    text = PAGE.read_text()
    if START not in text or END not in text:
        sys.exit(f"{PAGE.relative_to(ROOT)} has no deck-reference markers")
    head, rest = text.split(START, 1)
    _, tail = rest.split(END, 1)
    new = f"{head}{START}\n\n{render()}\n{END}{tail}"
    if "--check" in sys.argv:
        if new != text:
            sys.exit(
                f"{PAGE.relative_to(ROOT)} is out of date: run python3 tools/docs/deck_reference.py"
            )
        return
    PAGE.write_text(new)


if __name__ == "__main__":
    main()
