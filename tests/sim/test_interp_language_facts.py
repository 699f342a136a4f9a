"""The interpreter reads the language's facts from `melfa.lang.model` (one home), so the
checker and the simulator cannot disagree on arities, system variables or block pairing.
Sections (§) are those of ../shared/docs/melfa-basic-iv.md."""

from __future__ import annotations

import pytest

from melfa.lang import model
from melfa.lang.blocks import match_statements
from melfa.lang.parser import parse
from melfa.sim.interp import builtins, errors, sysvars
from tests.sim.test_interp_flow import fails, variables
from tests.sim.test_interp_values import ev, interp, run_error


def test_every_implemented_function_is_a_function_of_the_language() -> None:
    """§5: no function exists only in the simulator."""
    assert set(builtins.IMPLEMENTATIONS) <= set(model.FUNCTIONS)


@pytest.mark.parametrize("call", ["SIN(1, 2)", "DIST(P_CURR)", "ATN2(1)", 'MID$("A")'])
def test_wrong_argument_counts_stop_with_the_models_arity(call: str) -> None:
    """§5: the arity comes from the model; the message says how many it takes."""
    err = run_error(call)
    assert err.number == errors.SYNTAX_ERROR
    name = call.split("(")[0]
    assert f"takes {model.FUNCTIONS[name].arity_text} arguments" in err.message


def test_every_function_of_the_model_either_computes_or_says_it_is_not_simulated() -> None:
    """§5: a model function the simulator does not compute stops clearly, never silently."""
    for spec in model.FUNCTIONS.values():
        args = ", ".join(
            {None: "1", model.Kind.NUM: "1", model.Kind.STR: '"A"',
             model.Kind.POS: "P_CURR", model.Kind.JNT: "J_CURR"}[spec.param(i)]
            for i in range(spec.min_args)
        )  # fmt: skip
        try:
            ev(f"{spec.name}({args})")
        except errors.RunError as err:
            assert "takes" not in err.message, (spec.name, err.message)
            assert "not a MELFA BASIC IV function" not in err.message


def test_every_system_variable_is_read_or_refused_clearly() -> None:
    """§6: every status variable of the model is known to the simulator."""
    it = interp()
    for var in model.SYSTEM_VARIABLES.values():
        args = (lambda: 1,) if var.index is model.Index.REQUIRED else ()
        assert it.sysvars.getter(var.name, args) is not None, var.name


@pytest.mark.parametrize("name", ["M_IN", "M_HNDCQ", "P_CURR", "M_ERR", "C_TIME"])
def test_read_only_system_variables_cannot_be_assigned(name: str) -> None:
    """§6: assignability is the model's (`SystemVariable.assignable`)."""
    assert not model.SYSTEM_VARIABLES[name].assignable
    target = f"{name}(1)" if model.SYSTEM_VARIABLES[name].index is model.Index.REQUIRED else name
    value = {"P": "P_CURR", "C": '"X"'}.get(name[0], "1")
    number, line = fails(f"{target} = {value}", "END")
    assert (number, line) == (errors.TYPE_COMBINATION, 10)


def test_io_widths_are_the_models() -> None:
    assert sysvars.IO_WIDTHS["M_IN8"] == model.SYSTEM_VARIABLES["M_IN8"].io_width == 8


def test_block_pairing_is_the_languages_matcher() -> None:
    """§4.5: one matcher; a one-line IF … THEN BREAK leaves the loop in both."""
    text = "WHILE 1\nIF M1 > 2 THEN BREAK\nM1 = M1 + 1\nWEND\n"
    blocks = match_statements([ln.statement for ln in parse(text).lines])
    assert blocks.break_block[1][1] == 0 and blocks.break_target[1] == 3
    assert (
        variables("M1 = 0", "WHILE 1", "IF M1 > 2 THEN BREAK", "M1 = M1 + 1", "WEND", "END")["M1"]
        == 3
    )


def test_a_nested_select_stops_as_the_checker_says() -> None:
    """§4.5: SELECT cannot nest inside SELECT (L3254), in the checker and the simulator."""
    number, _ = fails(
        "M1 = 1", "SELECT M1", "CASE 1", "SELECT M1", "CASE 1", "END SELECT", "END SELECT", "END"
    )
    assert number == errors.SELECT_UNMATCH


def test_plt_as_a_value_runs() -> None:
    """§4.1: ``PLACE = PLT 1, M1`` (COSIMIR's IV palette example) is the same grid point
    as the parenthesised form."""
    v = variables(
        "P1 = (300, 0, 400, 180, 0, 180)(7, 0)",
        "P2 = (300, 100, 400, 180, 0, 180)(7, 0)",
        "P3 = (400, 0, 400, 180, 0, 180)(7, 0)",
        "DEF PLT 1, P1, P2, P3, , 3, 2, 1",
        "M1 = 2",
        "PLACE = PLT 1, M1",
        "PBOTH = (PLT 1, M1)",
        "END",
    )
    assert v["PLACE"] == v["PBOTH"]
    assert v["PLACE"] != v["P1"]


def test_pallet_and_interrupt_ranges_are_the_languages() -> None:
    """§4.6: pallets and DEF ACT priorities 1…8, the model's RANGES."""
    number, _ = fails("DEF ACT 9, M_IN(1) = 1 GOSUB *IRQ", "END", "*IRQ", "RETURN 1")
    assert number == errors.ARGUMENT_OUT_OF_RANGE
