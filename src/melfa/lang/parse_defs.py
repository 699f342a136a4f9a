"""The statements that declare: DEF INTE/FLOAT/DOUBLE/CHAR/POS/JNT, DEF IO, DEF PLT, DEF ACT,
DEF ARCH, DEF FN, DIM and ACT n = …, with the word meant when a DEF type is misspelt and the
MELFA BASIC V types named as such.

One family of the line parser (`melfa.lang.parser` dispatches to the ``st_`` methods).
"""

from __future__ import annotations

from melfa.lang import ast as A  # noqa: N812  (short alias: the parser builds many nodes)
from melfa.lang.model import V_DEF_TYPES
from melfa.lang.parse_cursor import WORD_KINDS, K, describe
from melfa.lang.parse_expr import ExprParser
from melfa.lang.tokens import Token
from melfa.lang.typos import suggest

_DEF_TYPES = {t.value: t for t in A.VarType}
_DEF_WORDS = (*_DEF_TYPES, "IO", "PLT", "ACT", "ARCH", "FN")
_IO_TYPES = {t.value: t for t in A.IOType}
_PLT_HINT = "Give the 8 values, e.g. DEF PLT 1, P1, P2, P3, , 4, 3, 1 (diagonal left out)."


class DefStatements(ExprParser):
    """DEF in its forms, DIM and ACT."""

    # definitions -------------------------------------------------------------------------

    def st_def(self, tok: Token) -> A.Statement:
        kind_tok = self.peek()
        word = kind_tok.text.upper() if kind_tok.kind in WORD_KINDS else ""
        if word in _DEF_TYPES:
            self.advance()
            names = [self.name(f"after DEF {word}")]
            while self.at_kind(K.COMMA):
                self.advance()
                names.append(self.name(f"in the DEF {word} list"))
            value = None
            if len(names) == 1 and self.at_op("="):
                self.advance()
                value = self.expr()
            return A.DefVar(_DEF_TYPES[word], tuple(names), value, self.last_span(tok))
        if word == "IO":
            self.advance()
            name = self.name("after DEF IO")
            self.expect_op("=", "after the DEF IO name")
            io_tok = self.peek()
            io_word = io_tok.text.upper() if io_tok.kind in WORD_KINDS else ""
            if io_word not in _IO_TYPES:
                guess = suggest(io_word, _IO_TYPES) if io_word else None
                raise self.fail(
                    io_tok,
                    f"Expected BIT, BYTE, WORD, INTEGER or DWORD, found {describe(io_tok)}",
                    suggestion=f"Write {guess} instead of {io_tok.text}."
                    if guess
                    else "Write the I/O type, e.g. DEF IO MSENSOR = BIT, 900.",
                    replacement=guess,
                )
            self.advance()
            self.expect_kind(K.COMMA, "','", "before the bit number")
            bit = self.expr()
            mask = None
            if self.at_kind(K.COMMA):
                self.advance()
                mask = self.expr()
            return A.DefIO(name, _IO_TYPES[io_word], bit, mask, self.last_span(tok))
        if word == "PLT":
            self.advance()
            items = self.arg_list(True)
            if len(items) != 8:
                raise self.fail(
                    tok,
                    "DEF PLT needs 8 values: number, start, end A, end B, [diagonal], "
                    f"count A, count B, direction (found {len(items)})",
                    "missing-argument" if len(items) < 8 else "too-many-arguments",
                    _PLT_HINT,
                )
            number, start, end_a, end_b, diag, count_a, count_b, direction = items
            if None in (number, start, end_a, end_b, count_a, count_b, direction):
                raise self.fail(
                    tok, "DEF PLT: only the diagonal point may be left out", suggestion=_PLT_HINT
                )
            assert number and start and end_a and end_b and count_a and count_b and direction
            return A.DefPlt(
                number,
                start,
                end_a,
                end_b,
                diag,
                count_a,
                count_b,
                direction,
                self.last_span(tok),
            )
        if word == "ACT":
            self.advance()
            priority = self.expr()
            self.expect_kind(K.COMMA, "','", "after the DEF ACT priority")
            condition = self.expr()
            if self.at_word("GOTO"):
                jkind = A.JumpKind.GOTO
            elif self.at_word("GOSUB"):
                jkind = A.JumpKind.GOSUB
            else:
                raise self.fail(
                    self.peek(),
                    f"Expected GOTO or GOSUB in DEF ACT, found {describe(self.peek())}",
                    suggestion="Write GOTO or GOSUB before the target, "
                    "e.g. DEF ACT 1, M_IN(1) = 1 GOSUB *STOP.",
                )
            self.advance()
            target = self.target("in DEF ACT")
            mode = None
            if self.at_kind(K.COMMA):
                self.advance()
                mtok = self.peek()
                if mtok.kind is K.IDENT and mtok.text.upper() in ("S", "L"):
                    self.advance()
                    mode = mtok.text.upper()
                else:
                    raise self.fail(
                        mtok,
                        f"Expected S or L, found {describe(mtok)}",
                        suggestion="Write S or L after the comma, or remove the comma.",
                    )
            return A.DefAct(priority, condition, jkind, target, mode, self.last_span(tok))
        if word == "ARCH":
            self.advance()
            items = self.arg_list(True)
            return A.Command(A.CommandKind.DEF_ARCH, tuple(items), self.last_span(tok))
        if kind_tok.kind is K.IDENT and word.startswith("FN") and len(word) > 2:
            self.advance()
            fname = A.Name(word, self.tok_span(kind_tok), kind_tok.text)
            params: list[A.Name] = []
            if self.at_kind(K.LPAREN):
                self.advance()
                if not self.at_kind(K.RPAREN):
                    params.append(self.name("in the DEF FN parameters"))
                    while self.at_kind(K.COMMA):
                        self.advance()
                        params.append(self.name("in the DEF FN parameters"))
                self.expect_kind(K.RPAREN, "')'", "after the DEF FN parameters")
            self.expect_op("=", "after the DEF FN name")
            body = self.expr()
            return A.DefFn(fname, tuple(params), body, self.last_span(tok))
        v_type = V_DEF_TYPES.get(word)
        if v_type is not None:
            raise self.v_construct(kind_tok, v_type)
        guess = suggest(word, _DEF_WORDS) if word else None
        if guess is not None:
            raise self.fail(
                kind_tok,
                f"Unknown DEF type {kind_tok.text}. Did you mean DEF {guess}?",
                "unknown-def-type",
                f"Replace with {guess}.",
                replacement=guess,
            )
        raise self.fail(
            kind_tok,
            "Expected a DEF type (INTE, FLOAT, DOUBLE, CHAR, POS, JNT, IO, PLT, ACT, ARCH or "
            f"FNname), found {describe(kind_tok)}",
            "unknown-def-type",
            "Write the type after DEF, e.g. DEF INTE MCOUNT.",
        )

    def st_dim(self, tok: Token) -> A.Statement:
        arrays: list[A.DimArray] = []
        while True:
            start = self.peek()
            name = self.name("after DIM")
            self.expect_kind(K.LPAREN, "'('", f"after DIM {name.written}")
            sizes = self.args(f"to close DIM {name.written}(")
            if not sizes:
                raise self.fail(
                    start,
                    f"DIM {name.written}() needs 1 to 3 sizes",
                    suggestion=f"Write the size in the parentheses, e.g. DIM {name.written}(10).",
                )
            arrays.append(A.DimArray(name, sizes, self.last_span(start)))
            if not self.at_kind(K.COMMA):
                break
            self.advance()
        return A.Dim(tuple(arrays), self.last_span(tok))

    def st_act(self, tok: Token) -> A.Statement:
        number = self.expr(6)  # stop before '='
        self.expect_op("=", "after ACT n")
        value = self.expr()
        return A.ActSet(number, value, self.last_span(tok))
