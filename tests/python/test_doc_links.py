"""Every relative link of README.md and docs/*.md resolves: the file exists and, for a `#anchor` into a Markdown
file, a heading of that file has that anchor under GitHub's rules (lowercase; punctuation other than `-` and `_`
removed; each space a `-`; the second heading of the same text `-1`, the third `-2`, ...). Code blocks and inline
code are skipped; web links (`https://...`, `mailto:`) are not fetched."""
import re
from functools import lru_cache
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
DOCS = [REPO / "README.md", *sorted((REPO / "docs").glob("*.md"))]

FENCE = re.compile(r"^\s*(```|~~~)")
HEADING = re.compile(r"^(#{1,6})\s+(.*?)\s*#*\s*$")
LINK = re.compile(r"\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")
EXTERNAL = re.compile(r"^([a-z][a-z0-9+.-]*:)", re.IGNORECASE)


def prose_lines(path):
    """(line number, text) of the lines outside fenced code blocks."""
    in_code = False
    for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
        if FENCE.match(line):
            in_code = not in_code
            continue
        if not in_code:
            yield number, line


def slug(heading):
    """GitHub's anchor of a heading's text."""
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", heading)      # a link in a heading: its text
    text = re.sub(r"[^\w\- ]", "", text.lower())
    return text.replace(" ", "-")


@lru_cache(maxsize=None)
def anchors(path):
    seen, result = {}, set()
    for _, line in prose_lines(path):
        match = HEADING.match(line)
        if not match:
            continue
        base = slug(match.group(2))
        count = seen.get(base, -1) + 1
        seen[base] = count
        result.add(base if count == 0 else f"{base}-{count}")
    return frozenset(result)


def broken_links(path, root=REPO):
    for number, line in prose_lines(path):
        for match in LINK.finditer(re.sub(r"`[^`]*`", "", line)):
            target = match.group(1)
            if EXTERNAL.match(target):
                continue
            file_part, _, anchor = target.partition("#")
            resolved = (path.parent / file_part).resolve() if file_part else path
            if not resolved.exists():
                yield f"{path.relative_to(root)}:{number}: {target}: no such file"
            elif anchor and resolved.suffix == ".md" and anchor not in anchors(resolved):
                yield f"{path.relative_to(root)}:{number}: {target}: no heading with this anchor"


def test_slug_follows_githubs_rules():
    assert slug("Our NPS-style host: `make sim`") == "our-nps-style-host-make-sim"
    assert slug("Cost (`make bench`, stage `sweep`)") == "cost-make-bench-stage-sweep"
    assert slug("Units of the report's parameters (it gives none but kg)") == \
        "units-of-the-reports-parameters-it-gives-none-but-kg"
    assert slug("See [the host](host.md)") == "see-the-host"


def test_anchors_number_repeated_headings(tmp_path):
    page = tmp_path / "page.md"
    page.write_text("# Tests\n```sh\n# Tests in code are no headings\n```\n## Tests\n### Tests\n", encoding="utf-8")
    assert anchors(page) == {"tests", "tests-1", "tests-2"}


def test_broken_links_are_found(tmp_path):
    (tmp_path / "other.md").write_text("# Other page\n", encoding="utf-8")
    page = tmp_path / "page.md"
    page.write_text("# Here\n[a](other.md#other-page) [b](#here) [c](https://example.org/x) `[d](gone.md)`\n"
                    "[e](gone.md) [f](other.md#nowhere) [g](#nowhere)\n", encoding="utf-8")
    assert list(broken_links(page, tmp_path)) == ["page.md:3: gone.md: no such file",
                                                  "page.md:3: other.md#nowhere: no heading with this anchor",
                                                  "page.md:3: #nowhere: no heading with this anchor"]


@pytest.mark.parametrize("path", DOCS, ids=lambda p: str(p.relative_to(REPO)))
def test_every_relative_link_resolves(path):
    assert list(broken_links(path)) == []
