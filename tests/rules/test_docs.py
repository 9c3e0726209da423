"""The user's documentation stays true: docs/settings.md is what gpu/settings.py makes,
the user guide keeps its one table of what the preview renders, approximates and leaves
out, the README stays a short front page, and no page points outside the repository."""
import re
from pathlib import Path

from lpv_preview.cli.settings_page import COMMAND, settings_page
from lpv_preview.gpu.settings import PARAMETERS, PRESETS

ROOT = Path(__file__).parents[2]
DOCS = ROOT / "docs"
README = ROOT / "README.md"
SET_UP_COMMANDS = ("bash scripts/setup.sh && .venv/bin/python -m lpv_preview demo",
                   "bash scripts/setup.sh && .venv/bin/python -m pytest -q -n 2 --dist loadfile tests")
"""The README's two commands: .ci/run and the tests' instructions depend on them."""
COVERAGE_HEADING = "## What the preview shows"
COVERAGE_COLUMNS = ("renders", "approximates", "leaves out")


def test_the_settings_page_is_what_gpu_settings_makes():
    assert (DOCS / "settings.md").read_text() == settings_page(), f"docs/settings.md is stale; run: {COMMAND}"


def test_no_preset_changes_an_expert_setting():
    experts = {name for name, field in PARAMETERS.items() if field.metadata["expert"]}
    assert experts and not experts & {name for values in PRESETS.values() for name in values}


def coverage_table(guide):
    """The rows of the user guide's table under COVERAGE_HEADING, each a list of cells."""
    section = guide.split(COVERAGE_HEADING, 1)[1].split("\n## ", 1)[0]
    lines = [line for line in section.splitlines() if line.startswith("|")]
    return [[cell.strip() for cell in line.strip().strip("|").split("|")] for line in lines]


def test_the_user_guide_has_one_table_of_what_the_preview_renders():
    guide = (DOCS / "user_guide.md").read_text()
    assert guide.count(COVERAGE_HEADING) == 1, f"docs/user_guide.md needs one section '{COVERAGE_HEADING}'"
    head, rule, *rows = coverage_table(guide)
    assert [cell.lower() for cell in head[1:]] == list(COVERAGE_COLUMNS)
    assert set("".join(rule)) <= set("-: ") and len(rows) >= 10
    for row in rows:
        assert len(row) == len(head) and row[0], f"a row of the table lacks cells: {row}"
        assert any(row[1:]), f"the row '{row[0]}' says nothing"


def test_the_readme_is_a_short_front_page():
    text = README.read_text()
    assert len(text.splitlines()) <= 100
    for command in SET_UP_COMMANDS:
        assert command in text
    for page in re.findall(r"\]\((docs/[^)#]+)", text):
        assert (ROOT / page).exists(), f"README.md links to {page}, which is missing"


def test_no_page_points_outside_the_repository():
    for page in [README, *DOCS.glob("*.md")]:
        text = page.read_text()
        assert "../shared" not in text and not re.search(r"\]\(\.\./", text), f"{page.name} points outside"
