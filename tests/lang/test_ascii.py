"""Upload text for an ASCII-only controller: accents in comments and strings become plain
letters; code is never touched."""

from __future__ import annotations

from pathlib import Path

from hypothesis import given, settings
from hypothesis import strategies as st

from melfa.lang.ascii import REPLACEMENT, ascii_fold, convert, find_non_ascii, to_controller_ascii
from melfa.lang.lexer import tokenize
from melfa.lang.plan import plan_upload
from melfa.lang.tokens import TokenKind

FREE = (TokenKind.COMMENT, TokenKind.STRING)
EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def code_tokens(text: str) -> list[tuple[TokenKind, str, int]]:
    return [(t.kind, t.text, t.line) for t in tokenize(text) if t.kind not in FREE]


def test_catalan_comments_become_plain_letters() -> None:
    program = "' Piràmide de peces\nMOV P1   ' repòs, peça\n' alçada d'una peça\nEND\n"
    text, changed = to_controller_ascii(program)
    assert text == "' Piramide de peces\nMOV P1   ' repos, peca\n' alcada d'una peca\nEND\n"
    assert changed == (1, 2, 3)


def test_strings_and_rem_comments() -> None:
    result = convert('PRINT "Mà cap avall"\nREM això\nMOV P1\n')
    assert result.text == 'PRINT "Ma cap avall"\nREM aixo\nMOV P1\n'
    assert (result.comment_lines, result.string_lines) == ((2,), (1,))
    assert result.note() == (
        "comments and strings on lines 1, 2 sent without accents; your file is unchanged"
    )


def test_code_is_never_touched() -> None:
    """A non-ASCII name is the checker's L4310; it stays as written for it to report."""
    program = "MPEÇA = 1 ' peça\n"
    text, changed = to_controller_ascii(program)
    assert text == "MPEÇA = 1 ' peca\n"
    assert changed == (1,)
    assert find_non_ascii(text) is not None


def test_no_ascii_form_becomes_a_question_mark() -> None:
    assert ascii_fold("Straße 5 €") == f"Stra{REPLACEMENT}e 5 {REPLACEMENT}"
    assert ascii_fold("ﬁ ½") == "fi 1?2"  # NFKD compatibility forms, then ? for the fraction


def test_a_string_stays_one_string() -> None:
    """NFKD of a full-width quote is `"`, which would end the string early."""
    text, _ = to_controller_ascii('PRINT "a＂b"\n')
    assert text == 'PRINT "a?b"\n'
    assert [t.kind for t in tokenize(text)] == [t.kind for t in tokenize('PRINT "abc"\n')]


def test_ascii_program_is_returned_unchanged() -> None:
    program = "10 MOV P1 ' ok\n20 END\n"
    assert to_controller_ascii(program) == (program, ())
    assert convert(program).note() is None


def test_the_bundled_pyramid_example() -> None:
    source = (EXAMPLES / "pyramid.MB4").read_text(encoding="utf-8")
    text, changed = to_controller_ascii(source)
    assert text.isascii()
    assert changed and changed[0] == 1
    assert code_tokens(text) == code_tokens(source)
    assert len(text.splitlines()) == len(source.splitlines())


@settings(max_examples=60, deadline=None)
@given(
    st.lists(
        st.sampled_from(
            ["MOV P1", "' àéïõü ç ß €", 'PRINT "Peça ＂ ½"', "M1 = 2 ' ñ", "REM ø", "*LBL", "END"]
        ),
        max_size=12,
    )
)
def test_only_comments_and_strings_change(lines: list[str]) -> None:
    program = "\n".join(lines) + "\n"
    text, changed = to_controller_ascii(program)
    assert text.isascii()
    assert code_tokens(text) == code_tokens(program)
    assert [t.kind for t in tokenize(text)] == [t.kind for t in tokenize(program)]
    differ = {
        n
        for n, (a, b) in enumerate(zip(program.splitlines(), text.splitlines(), strict=True), 1)
        if a != b
    }
    assert set(changed) == differ


def test_every_upload_path_folds_accents_before_numbering() -> None:
    """The web IDE and the service upload through `plan_upload` too, not only the CLI:
    a program with Catalan comments becomes numbered ASCII items, line for line."""
    items = plan_upload("' Piràmide\nMOV P1 ' repòs\nGOTO *FI\n*FI\nEND").items
    assert [item.text for item in items] == [
        "10 ' Piramide",
        "20 MOV P1 ' repos",
        "30 GOTO *FI",
        "40 *FI",
        "50 END",
    ]
    assert all(item.text.isascii() for item in items)
