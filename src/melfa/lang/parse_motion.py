"""The statements that act: moves (MOV, MVS, the arcs, MVA, with their TYPE and WTH/WTHIF
parts), the keyword-and-arguments commands (``OVRD 50``, ``HOPEN 1``, ``DLY 0.5``, their
argument counts from `melfa.lang.grammar.COMMANDS`), the ON/OFF switches and CMP.

One family of the line parser (`melfa.lang.parser` dispatches to the ``st_`` methods).
"""

from __future__ import annotations

from melfa.lang import ast as A  # noqa: N812  (short alias: the parser builds many nodes)
from melfa.lang.parse_cursor import END_KINDS, WORD_KINDS, K, describe
from melfa.lang.parse_expr import ExprParser
from melfa.lang.tokens import Token

_MOVE_KINDS = {k.value: k for k in A.MoveKind}
_SWITCH_KINDS = {k.value: k for k in A.SwitchKind}
_ARC_KINDS = {k.value: k for k in A.ArcKind}

# One example each, for "Add a value after OVRD, e.g. OVRD 50." (missing-argument).
_COMMAND_EXAMPLES: dict[str, str] = {
    "OVRD": "OVRD 50",
    "JOVRD": "JOVRD 50",
    "SPD": "SPD 100",
    "CNT": "CNT 1",
    "FINE": "FINE 100",
    "LOADSET": "LOADSET 1, 1",
    "TORQ": "TORQ 4, 10",
    "JRC": "JRC 1",
    "HOPEN": "HOPEN 1",
    "HCLOSE": "HCLOSE 1",
    "TOOL": "TOOL (0, 0, 100, 0, 0, 0)",
    "BASE": "BASE P_NBASE",
    "DLY": "DLY 0.5",
    "ERROR": "ERROR 9100",
    "CALLP": 'CALLP "P10"',
    "XLOAD": 'XLOAD 2, "P1"',
    "XRUN": 'XRUN 2, "P1"',
    "XSTP": "XSTP 2",
    "XRST": "XRST 2",
    "XCLR": "XCLR 2",
    "PRIORITY": "PRIORITY 1",
    "GETM": "GETM 1",
    "CLR": "CLR 1",
}


class MotionStatements(ExprParser):
    """Moves, commands, switches and CMP."""

    def command(
        self, tok: Token, kind: A.CommandKind, lo: int, hi: int, empties: bool
    ) -> A.Command:
        args = self.arg_list(empties)
        word = kind.value
        if len(args) < lo:
            what = "a value" if lo == 1 else f"{lo} values"
            if word in ("HOPEN", "HCLOSE"):
                what = "a hand number (1 to 8)"
            example = _COMMAND_EXAMPLES.get(word)
            raise self.fail(
                self.peek(),
                f"{word} needs {what}, found {describe(self.peek())}",
                "missing-argument",
                f"Add {what} after {word}" + (f", e.g. {example}." if example else "."),
            )
        if len(args) > hi:
            values = f"{hi} value{'s' if hi != 1 else ''}"
            raise self.fail(
                tok,
                f"{word} takes at most {values}, found {len(args)}",
                "too-many-arguments",
                f"Remove the extra values: {word} takes at most {values}."
                if hi
                else f"Remove the values after {word}.",
            )
        return A.Command(kind, tuple(args), self.last_span(tok))

    # movement ---------------------------------------------------------------------

    def move_tail(self) -> tuple[A.MoveType | None, A.Appended | None]:
        if self.toks[self.i].kind in END_KINDS:  # the usual case: nothing after the target
            return None, None
        mtype = None
        if self.at_word("TYPE"):
            t = self.advance()
            c1 = self.expr()
            c2 = None
            if self.at_kind(K.COMMA):
                self.advance()
                c2 = self.expr()
            mtype = A.MoveType(c1, c2, self.last_span(t))
        appended = None
        if self.at_word("WTH") or self.at_word("WTHIF"):
            t = self.advance()
            condition = None
            if t.text.upper() == "WTHIF":
                condition = self.expr()
                self.expect_kind(K.COMMA, "','", "after the WTHIF condition")
            action = self.appended_action()
            appended = A.Appended(condition, action, self.last_span(t))
        return mtype, appended

    def appended_action(self) -> A.Statement:
        tok = self.toks[self.i]
        if tok.kind is K.KEYWORD and tok.text.upper() in ("HLT", "SKIP"):
            self.i += 1
            kind = A.CommandKind.HLT if tok.text.upper() == "HLT" else A.CommandKind.SKIP
            return A.Command(kind, (), self.tok_span(tok))
        if tok.kind is K.IDENT:
            target = self.assign_target()
            return self.assignment_rest(target, tok)
        raise self.fail(
            tok,
            f"Expected an assignment, HLT or SKIP after WTH/WTHIF, found {describe(tok)}",
            suggestion="Write what to do during the move, e.g. WTH M_OUT(17) = 1.",
        )

    def target_expr(self, word: str) -> A.Expr:
        if self.at_end():
            raise self.fail(
                self.peek(),
                f"{word} needs a target position",
                "missing-argument",
                f"Add the position to move to, e.g. {word} P1.",
            )
        return self.expr()

    def st_move(self, tok: Token) -> A.Statement:
        word = tok.text.upper()
        kind = _MOVE_KINDS[word]
        target: A.Expr | None = None
        close: A.Expr | None = None
        if kind is A.MoveKind.MVS and self.at_kind(K.COMMA):
            self.advance()
            close = self.expr()
        else:
            target = self.target_expr(word)
            if self.at_kind(K.COMMA):
                self.advance()
                close = self.expr()
        mtype, appended = self.move_tail()
        return A.Move(kind, target, close, mtype, appended, self.last_span(tok))

    def st_arc(self, tok: Token) -> A.Statement:
        word = tok.text.upper()
        points = [self.target_expr(word)]
        while self.at_kind(K.COMMA):
            self.advance()
            points.append(self.expr())
        if len(points) != 3:
            raise self.fail(
                tok,
                f"{word} needs 3 positions (start, {'via' if word != 'MVR3' else 'end'}, …), "
                f"found {len(points)}",
                "missing-argument" if len(points) < 3 else "too-many-arguments",
                f"Give {word} three positions, e.g. {word} P1, P2, P3.",
            )
        mtype, appended = self.move_tail()
        return A.ArcMove(_ARC_KINDS[word], tuple(points), mtype, appended, self.last_span(tok))

    def st_mva(self, tok: Token) -> A.Statement:
        target = self.target_expr("MVA")
        arch = None
        if self.at_kind(K.COMMA):
            self.advance()
            arch = self.expr()
        _, appended = self.move_tail()
        return A.ArchMove(target, arch, appended, self.last_span(tok))

    # switches -----------------------------------------------------------------------

    def on_off(self, word: str) -> bool:
        if self.at_word("ON"):
            self.advance()
            return True
        if self.at_word("OFF"):
            self.advance()
            return False
        raise self.fail(
            self.peek(),
            f"Expected ON or OFF after {word}, found {describe(self.peek())}",
            suggestion=f"Write {word} ON or {word} OFF.",
        )

    def st_switch(self, tok: Token) -> A.Statement:
        word = tok.text.upper()
        on = self.on_off(word)
        extra: list[A.Expr] = []
        while self.at_kind(K.COMMA):
            self.advance()
            extra.append(self.expr())
        return A.Switch(_SWITCH_KINDS[word], on, tuple(extra), self.last_span(tok))

    def st_cmp(self, tok: Token) -> A.Statement:
        nxt = self.peek()
        mode_word = nxt.text.upper() if nxt.kind in WORD_KINDS else ""
        if mode_word == "OFF":
            self.advance()
            return A.Cmp(A.CmpMode.OFF, None, self.last_span(tok))
        if mode_word not in ("JNT", "POS", "TOOL"):
            raise self.fail(
                nxt,
                f"Expected JNT, POS, TOOL or OFF after CMP, found {describe(nxt)}",
                suggestion="Write CMP JNT, CMP POS or CMP TOOL with a mask, or CMP OFF.",
            )
        self.advance()
        self.expect_kind(K.COMMA, "','", f"after CMP {mode_word}")
        mask = self.expr()
        return A.Cmp(A.CmpMode(mode_word), mask, self.last_span(tok))
