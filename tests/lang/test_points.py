"""Points files: reading both forms, diagnostics that say what and where, writing back."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from melfa.lang.diagnostics import Severity
from melfa.lang.points import PointDef, PointKind
from melfa.lang.points_read import parse_points
from melfa.lang.points_write import format_points, format_value, upload_lines

# The thesis's points file (§7.2, test 3), verbatim.
THESIS_POS = """\
DEF POS Ppiram=(417.61,16.40,180.00,180.00,0.00,180.00)(7,0)
DEF POS PINIC=(524.49,80.98,614.92,-179.99,0.00,-93.07)(7,0)
DEF POS Ppal=(455.41,-481.70,419.17,-174.93,0.87,-140.23)(7,0)
DEF POS PCOLOC=(418.00,479.40,221.80,-177.00,0.00,-90.00)(7,0)
"""


def errors(text: str) -> list[tuple[int, int, str | None, str]]:
    return [
        (d.line, d.column, d.code, d.message)
        for d in parse_points(text).diagnostics
        if d.severity is Severity.ERROR
    ]


def test_thesis_file_reads_clean_and_writes_back_identically() -> None:
    f = parse_points(THESIS_POS)
    assert f.diagnostics == ()
    assert [p.name for p in f.points] == ["Ppiram", "PINIC", "Ppal", "PCOLOC"]
    assert f.points[1].values == (524.49, 80.98, 614.92, -179.99, 0.0, -93.07)
    assert (f.points[1].fl1, f.points[1].fl2) == (7, 0)
    assert [p.line for p in f.points] == [1, 2, 3, 4]
    assert format_points(f.points) == THESIS_POS


def test_upload_form_strips_def_pos() -> None:
    f = parse_points(THESIS_POS)
    assert upload_lines(f.points)[0] == "Ppiram=(417.61,16.40,180.00,180.00,0.00,180.00)(7,0)"


def test_upload_form_is_accepted_as_input_and_kind_comes_from_the_name() -> None:
    f = parse_points("Pa=(1,2,3,4,5,6)(6,0)\nJhome=(0,0,90,0,90,0)\n")
    assert f.diagnostics == ()
    assert f.points == (
        PointDef.pos("Pa", (1, 2, 3, 4, 5, 6), fl1=6),
        PointDef.jnt("Jhome", (0, 0, 90, 0, 90, 0)),
    )


def test_listp_style_signed_values_are_read() -> None:
    f = parse_points("P1=(+400.13,+0.00,+644.62,+180.00,+0.00,+180.00)(7,0)")
    assert f.points[0].values == (400.13, 0.0, 644.62, 180.0, 0.0, 180.0)


def test_def_jnt_and_case_insensitive_keywords() -> None:
    f = parse_points(
        "def jnt J1=(0, 10, 80, 10, 90, 0)\n  DEF   POS   Pz = ( 1 , 2,3,4,5,6 ) ( 7 , 0 )"
    )
    assert f.diagnostics == ()
    assert f.points[0].kind is PointKind.JNT
    assert f.points[0].values[2] == 80.0
    assert f.points[1].values == (1, 2, 3, 4, 5, 6)


def test_comments_blank_lines_and_crlf_are_skipped_and_lines_still_count() -> None:
    text = (
        "' points for the pyramid\r\n\r\nREM taught 2024\r\n"
        "DEF POS Pa=(1,2,3,4,5,6)(7,0) ' home\r\n"
    )
    f = parse_points(text)
    assert f.diagnostics == ()
    assert f.points[0].line == 4
    assert f.points[0].name == "Pa"


def test_omitted_elements_are_none_and_written_back_empty() -> None:
    f = parse_points("DEF POS Pa=(400,0,,180,,180)(7,0)")
    assert f.diagnostics == ()
    assert f.points[0].values == (400.0, 0.0, None, 180.0, None, 180.0)
    assert format_points(f.points) == "DEF POS Pa=(400.00,0.00,,180.00,,180.00)(7,0)\n"


def test_eight_elements_with_additional_axes() -> None:
    f = parse_points("DEF POS Pa=(1,2,3,4,5,6,7,8)(7,0)")
    assert f.diagnostics == ()
    assert len(f.points[0].values) == 8


def test_hex_fl2_is_read_and_written_as_hex() -> None:
    f = parse_points("DEF POS Pa=(1,2,3,4,5,6)(7,&H00100000)")
    assert f.points[0].fl2 == 1048576
    assert upload_lines(f.points) == ["Pa=(1.00,2.00,3.00,4.00,5.00,6.00)(7,&H00100000)"]


def test_decimal_and_negative_fl2() -> None:
    f = parse_points(
        "Pa=(1,2,3,4,5,6)(7,1048576)\nPb=(1,2,3,4,5,6)(7,-1)\nPc=(1,2,3,4,5,6)(&B101,0)"
    )
    assert [(p.fl1, p.fl2) for p in f.points] == [(7, 1048576), (7, 0xFFFFFFFF), (5, 0)]


def test_missing_flags_default_to_7_0_with_an_info() -> None:
    f = parse_points("DEF POS Pa=(1,2,3,4,5,6)")
    assert (f.points[0].fl1, f.points[0].fl2) == (7, 0)
    [d] = f.diagnostics
    assert d.severity is Severity.INFO
    assert "(7,0)" in d.message
    assert not f.has_errors


def test_empty_flags_are_rt_toolbox_no_data() -> None:
    # RT ToolBox exports a position never taught as (0.00,…)(,) [S2 p.146, S10]: defined
    # for the program, but nothing to upload or to judge against the arm's reach.
    f = parse_points("Pa=(0.00,0.00,0.00,0.00,0.00,0.00)(,)")
    assert f.points == () and f.names == ("Pa",)
    assert [(d.severity, d.rule) for d in f.diagnostics] == [(Severity.INFO, "points-no-data")]
    f = parse_points("Pa=(400,0,600,180,0,180)(,0)")  # one flag omitted: still the default
    assert (f.points[0].fl1, f.points[0].fl2) == (7, 0)


def test_bad_number_points_at_the_element() -> None:
    text = "DEF POS Pa=(1,2,abc,4,5,6)(7,0)"
    [(line, col, code, message)] = errors(text)
    assert (line, col, code) == (1, text.index("abc") + 1, "L3860")
    assert "Z" in message and "abc" in message
    f = parse_points(text)
    assert f.points == ()
    assert f.names == ("Pa",)  # a program using Pa is not flagged a second time
    assert f.diagnostics[0].end_column == text.index("abc") + 4


def test_wrong_element_count() -> None:
    [(line, col, code, message)] = errors("\n\nPa=(1,2,3,4,5)(7,0)")
    assert (line, col, code) == (3, 4, "L3860")
    assert "5 elements" in message


def test_too_many_elements() -> None:
    assert "9 elements" in errors("Pa=(1,2,3,4,5,6,7,8,9)(7,0)")[0][3]


def test_joint_with_flags_is_an_error() -> None:
    [(_, _, _, message)] = errors("DEF JNT Ja=(1,2,3,4,5,6)(7,0)")
    assert "no structure flags" in message


def test_name_must_match_kind() -> None:
    [(_, col, code, message)] = errors("DEF POS Home=(1,2,3,4,5,6)(7,0)")
    assert (col, code) == (9, "L4390")
    assert "start with P" in message
    assert "start with J" in errors("DEF JNT Pa=(1,2,3,4,5,6)")[0][3]


def test_upload_form_with_other_first_letter_is_an_error() -> None:
    [(_, _, _, message)] = errors("Home=(1,2,3,4,5,6)(7,0)")
    assert "P" in message and "J" in message


def test_name_longer_than_8_characters() -> None:
    [(_, _, code, message)] = errors("Pabcdefgh=(1,2,3,4,5,6)(7,0)")
    assert code == "L4300"
    assert "9 characters" in message
    assert errors("Pabcdefg=(1,2,3,4,5,6)(7,0)") == []


@pytest.mark.parametrize("name", ["P-1", "P.1", "Pé", "1P", "P 1"])
def test_illegal_characters_in_names(name: str) -> None:
    assert errors(f"DEF POS {name}=(1,2,3,4,5,6)(7,0)") != []


def test_underscore_second_is_a_warning_further_on_a_name_as_in_programs() -> None:
    f = parse_points("P_01=(1,2,3,4,5,6)(7,0)")
    assert [d.severity for d in f.diagnostics] == [Severity.WARNING]
    assert len(f.points) == 1
    f = parse_points("pSafe_1=(1,2,3,4,5,6)(7,0)\npallet_A=(1,2,3,4,5,6)(7,0)\n")
    assert (f.diagnostics, [p.name for p in f]) == ((), ["pSafe_1", "pallet_A"])


def test_duplicates_ignore_case_and_name_the_first_line() -> None:
    [(line, _, code, message)] = errors("Pa=(1,2,3,4,5,6)(7,0)\nPA=(1,2,3,4,5,6)(7,0)")
    assert (line, code) == (2, "L4350")
    assert "line 1" in message


def test_get_ignores_case() -> None:
    f = parse_points(THESIS_POS)
    point = f.get("ppiram")
    assert point is not None and point.name == "Ppiram"
    assert f.get("Pnone") is None


@pytest.mark.parametrize(
    "text",
    [
        "DEF INTE M1",
        "just words",
        "Pa=",
        "Pa=(1,2,3,4,5,6",
        "Pa=(1,2,3,4,5,6)(7,0) extra",
        "Pa=(1,2,3,4,5,6)(7)",
        "Pa=(1,2,3,4,5,6)(7.5,0)",
        "Pa=(1,2,3,4,5,6)(9,0)",
        "Pa=(1,2,3,4,5,6)(7,&H123456789)",
        "=(1,2,3,4,5,6)(7,0)",
    ],
)
def test_malformed_lines_give_an_error_on_that_line(text: str) -> None:
    f = parse_points("' first\n" + text)
    errs = [d for d in f.diagnostics if d.is_error]
    assert errs, text
    assert all(d.line == 2 for d in errs)
    assert f.points == ()


def test_a_bad_line_does_not_hide_the_next() -> None:
    f = parse_points("Pa=(1,2\nPb=(1,2,3,4,5,6)(7,0)\nPc=(x)")
    assert [p.name for p in f.points] == ["Pb"]
    assert [d.line for d in f.diagnostics] == [1, 3]


def test_format_value_rounds_to_two_decimals() -> None:
    assert format_value(1.005) in ("1.00", "1.01")  # binary floating point; either is fine
    assert format_value(-179.994) == "-179.99"
    assert format_value(-0.004) == "0.00"


def test_pointdef_refuses_inconsistent_values() -> None:
    with pytest.raises(ValueError):
        PointDef("Pa", PointKind.POS, (1, 2, 3))
    with pytest.raises(ValueError):
        PointDef("Ja", PointKind.JNT, (1, 2, 3, 4, 5, 6), fl1=7, fl2=0)
    with pytest.raises(ValueError):
        PointDef("Pa", PointKind.POS, (1, 2, 3, 4, 5, 6))


# --- round trip ----------------------------------------------------------------------

_hundredths = st.integers(min_value=-99_999_99, max_value=99_999_99).map(lambda n: n / 100)
_element = st.one_of(st.none(), _hundredths)
_values = st.lists(_element, min_size=6, max_size=8).map(tuple)
_suffix = st.text(
    alphabet="ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789", max_size=7
)


@st.composite
def _points(draw: st.DrawFn) -> list[PointDef]:
    out: list[PointDef] = []
    seen: set[str] = set()
    for _ in range(draw(st.integers(0, 6))):
        kind = draw(st.sampled_from(PointKind))
        name = ("P" if kind is PointKind.POS else "J") + draw(_suffix)
        if name.upper() in seen:
            continue
        seen.add(name.upper())
        if kind is PointKind.POS:
            fl1 = draw(st.integers(0, 7))
            fl2 = draw(st.integers(0, 0xFFFFFFFF))
            out.append(PointDef.pos(name, draw(_values), fl1, fl2))
        else:
            out.append(PointDef.jnt(name, draw(_values)))
    return out


@given(_points())
def test_format_then_parse_gives_the_same_points(points: list[PointDef]) -> None:
    f = parse_points(format_points(points))
    assert [d for d in f.diagnostics if d.severity is not Severity.INFO] == []
    assert list(f.points) == points


@given(_points())
def test_upload_lines_read_back_as_the_same_points(points: list[PointDef]) -> None:
    f = parse_points("\n".join(upload_lines(points)))
    assert list(f.points) == points


@given(st.text(max_size=200))
def test_any_text_gives_points_and_diagnostics_never_an_exception(text: str) -> None:
    f = parse_points(text)
    lines = text.replace("\r\n", "\n").replace("\r", "\n").split("\n")
    for d in f.diagnostics:
        assert 1 <= d.line <= len(lines)
        assert 1 <= d.column <= d.end_column <= len(lines[d.line - 1]) + 1


def test_a_misnamed_point_gets_a_rename_it_can_use() -> None:
    [d] = parse_points("DEF POS Home=(1,2,3,4,5,6)(7,0)").diagnostics
    assert d.suggestion == "Rename it PHome."
    [d] = parse_points("DEF JNT Pa=(1,2,3,4,5,6)").diagnostics
    assert d.suggestion == "Rename it JPa."
    [d] = parse_points("DEF POS Homeward=(1,2,3,4,5,6)(7,0)").diagnostics
    assert d.suggestion == "Rename it Pomeward."  # 8 characters already: swap the first
