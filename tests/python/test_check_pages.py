"""scripts/check_pages.py: the history share of the results pages and the README's results table."""
import importlib.util
import os

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
spec = importlib.util.spec_from_file_location("check_pages", os.path.join(ROOT, "scripts", "check_pages.py"))
check_pages = importlib.util.module_from_spec(spec)
spec.loader.exec_module(check_pages)

CURRENT = """# Results

| method | mAP |
| --- | --- |
| Coulomb | 0.926 |
| classical MDS | 0.787 |

Coulomb retrieves best under the paper's distance (`cshapes experiment paper --data DATA --out OUT`).
"""


def write(tmp_path, name, text):
    path = tmp_path / name
    path.write_text(text)
    return str(path)


def test_a_page_of_current_results_passes(tmp_path):
    assert check_pages.history_share([write(tmp_path, "r.md", CURRENT)], 5.0) == 0


@pytest.mark.parametrize("history", [
    "Measured on 2026-11-26 with the previous defaults: mAP 0.882.",
    "Re-measured after commit `0a200eb`, the heat method gives 2.28%.",
    "The old defaults kept the pose until the start changed (issue 34).",
])
def test_a_page_mostly_history_fails(tmp_path, history):
    page = write(tmp_path, "r.md", CURRENT + "\n" + "\n\n".join([history] * 5) + "\n")
    assert check_pages.history_share([page], 5.0) == 1


def test_code_blocks_and_protocol_words_are_not_history(tmp_path):
    text = CURRENT + "\n```sh\n# 2026-11-26 in a comment of a command\n```\n\nJudge data never used to choose.\n"
    assert check_pages.history_share([write(tmp_path, "r.md", text)], 5.0) == 0


def test_the_results_section_is_read_from_mkdocs_yml():
    pages = [os.path.basename(p) for p in check_pages.results_pages(os.path.join(ROOT, "mkdocs.yml"))]
    assert "results.md" in pages and "benchmarks.md" in pages
    assert "changelog.md" not in pages and "notes.md" not in pages


README = """# x

## Results at a glance

| method | mAP |
| --- | --- |
| Coulomb | 0.926 |
| classical MDS | 0.787 |
"""


def test_the_readme_table_must_be_the_results_pages(tmp_path):
    readme = write(tmp_path, "README.md", README)
    assert check_pages.readme_table(readme, write(tmp_path, "ok.md", CURRENT)) == 0
    assert check_pages.readme_table(readme, write(tmp_path, "num.md", CURRENT.replace("0.787", "0.772"))) == 1
    assert check_pages.readme_table(readme, write(tmp_path, "row.md", CURRENT.replace("| classical MDS | 0.787 |\n", ""))) == 1
    assert check_pages.readme_table(readme, write(tmp_path, "none.md", "# nothing\n")) == 1
