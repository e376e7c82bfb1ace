# The README's first screen (issue 62): the two commands first, a figure of what the main job
# gives, where to go next; every file it names exists; the commands table one short line a row.
import os
import re

from conftest import SOURCE_DIR

README = os.path.join(SOURCE_DIR, "README.md")


def readme_lines():
    with open(README) as f:
        return f.read().split("\n")


def test_the_readme_starts_with_exactly_the_two_commands():
    lines = readme_lines()
    assert lines[0].startswith("# ")
    start = lines.index("```")
    assert start <= 3, "the commands come first"
    end = lines.index("```", start + 1)
    commands = [ln.split("#")[0].strip() for ln in lines[start + 1:end]]
    assert commands == ["bash scripts/main.sh", "bash scripts/test.sh"]


def test_the_first_screen_shows_a_figure_and_where_to_go_next():
    lines = readme_lines()
    first = "\n".join(lines[:60])
    figures = re.findall(r"!\[[^\]]*\]\(([^)]+)\)", first)
    assert figures, "a figure of what the main job gives"
    for f in figures:
        assert os.path.isfile(os.path.join(SOURCE_DIR, f)), f
    assert "## Where to go next" in first


def test_every_path_the_readme_names_exists():
    text = "\n".join(readme_lines())
    paths = set(re.findall(r"`((?:docs|scripts|examples|studies|tools|bench|src|tests)/[^` ]+)`", text))
    paths |= set(re.findall(r"\]\(((?:docs)/[^)]+)\)", text))
    assert len(paths) >= 10
    missing = [p for p in sorted(paths) if not os.path.exists(os.path.join(SOURCE_DIR, p.rstrip("/")))]
    assert not missing, missing


def test_the_commands_table_has_one_short_line_a_row():
    lines = readme_lines()
    at = lines.index("## Commands")
    rows = [ln for ln in lines[at:] if ln.startswith("| `")]
    assert len(rows) >= 8
    for row in rows:
        assert len(row) <= 140, row
