"""docs/tools-map.md names every file of tools/ in the section of its folder, and every part of tools/finken/ says in
its docstring what it holds: a module added without a line in the map, or a part without a docstring, fails here."""
import ast
import re
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
TOOLS = REPO / "tools"
SECTION = re.compile(r"^## .*\(`((?:tools|finken)/[\w/]*)`\)\s*$")


def sections():
    """{folder relative to tools/ ("" for tools/ itself): the text of its section} of docs/tools-map.md."""
    found, current = {}, None
    for line in (REPO / "docs" / "tools-map.md").read_text().splitlines():
        heading = SECTION.match(line)
        if heading:
            current = heading.group(1).removeprefix("tools/").rstrip("/")
            found[current] = ""
        elif line.startswith("## "):
            current = None
        elif current is not None:
            found[current] += line + "\n"
    return found


def test_every_tool_and_module_has_its_line_in_its_folders_section():
    text = sections()
    files = [p for p in TOOLS.rglob("*") if p.is_file() and p.suffix in (".py", ".sh", ".txt")
             and "__pycache__" not in p.parts and p.name != "__init__.py"]
    assert len(files) > 80
    missing = [str(p.relative_to(TOOLS)) for p in files
               if f"`{p.name}`" not in text.get(str(p.parent.relative_to(TOOLS)).replace(".", ""), "")]
    assert missing == []


def test_every_part_of_the_package_says_what_it_holds():
    parts = [p for p in (TOOLS / "finken").rglob("*") if p.is_dir() and p.name != "__pycache__"]
    assert len(parts) >= 8
    for part in [TOOLS / "finken", *parts]:
        docstring = ast.get_docstring(ast.parse((part / "__init__.py").read_text()))
        assert docstring and len(docstring.splitlines()) >= 3, part
        # each module of the part is named in its docstring
        for module in part.glob("*.py"):
            if module.name != "__init__.py" and part != TOOLS / "finken":
                assert module.stem in docstring, (part.name, module.stem)
