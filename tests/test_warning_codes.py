"""Every warning carries a registered, stable snake_case code, and every registered code is raised somewhere."""

import re
from pathlib import Path

import pytest

from massline.identify.warning_codes import CODES, CodedWarning, codes_of

ROOT = Path(__file__).resolve().parent.parent
RAISED = re.compile(r'CodedWarning\(\s*"([^"]+)"')


def raised_codes() -> set[str]:
    """The codes the package's source passes to CodedWarning (its first argument, a literal)."""
    sources = [p for p in ROOT.rglob("*.py") if not {"tests", ".venv"} & set(p.relative_to(ROOT).parts)]
    return {code for path in sources for code in RAISED.findall(path.read_text())}


def test_the_codes_are_snake_case_and_each_says_what_it_means():
    assert all(re.fullmatch(r"[a-z0-9]+(_[a-z0-9]+)*", code) for code in CODES)
    assert all(len(meaning) > 20 for meaning in CODES.values())


def test_every_raised_code_is_registered_and_every_registered_code_is_raised():
    raised = raised_codes()
    assert raised == set(CODES), (raised - set(CODES), set(CODES) - raised)


def test_an_unregistered_code_is_a_programming_error():
    with pytest.raises(ValueError, match="unregistered warning code"):
        CodedWarning("something_odd", "a sentence")


def test_a_warning_prints_its_sentence_and_serialises_with_its_code():
    warning = CodedWarning("few_lines", "the band holds only 12 spectral lines")
    assert str(warning) == f"{warning}" == "the band holds only 12 spectral lines"
    assert warning.as_json() == {"code": "few_lines", "text": "the band holds only 12 spectral lines"}
    assert codes_of([warning, warning]) == {"few_lines"}
