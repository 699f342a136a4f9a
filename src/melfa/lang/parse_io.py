"""The statements of files and communication: OPEN, PRINT, INPUT, CLOSE and COM ON/OFF/STOP.

One family of the line parser (`melfa.lang.parser` dispatches to the ``st_`` methods).
"""

from __future__ import annotations

from melfa.lang import ast as A  # noqa: N812  (short alias: the parser builds many nodes)
from melfa.lang.parse_cursor import WORD_KINDS, K, describe
from melfa.lang.parse_expr import ExprParser
from melfa.lang.tokens import Token


class IOStatements(ExprParser):
    """Files and the serial port."""

    # files and communication -----------------------------------------------------------

    def channel(self) -> A.Expr:
        if self.at_op("#"):
            self.advance()
        return self.expr()

    def st_open(self, tok: Token) -> A.Statement:
        file = self.expr()
        mode = None
        if self.at_word("FOR"):
            self.advance()
            mtok = self.peek()
            mword = mtok.text.upper() if mtok.kind in WORD_KINDS else ""
            if mword not in ("INPUT", "OUTPUT", "APPEND"):
                raise self.fail(
                    mtok,
                    f"Expected INPUT, OUTPUT or APPEND, found {describe(mtok)}",
                    suggestion="Write FOR INPUT, FOR OUTPUT or FOR APPEND.",
                )
            self.advance()
            mode = A.FileMode(mword)
        self.expect_word("AS", "in OPEN … AS #n")
        number = self.channel()
        return A.Open(file, mode, number, self.last_span(tok))

    def st_print(self, tok: Token) -> A.Statement:
        channel = None
        if self.at_op("#"):
            channel = self.channel()
            if not self.at_end():
                self.expect_kind(K.COMMA, "','", "after the PRINT channel")
        items: list[A.Expr] = []
        while not self.at_end():
            items.append(self.expr())
            if self.at_kind(K.COMMA) or self.at_op(";"):
                self.advance()
                continue
            break
        return A.Print(channel, tuple(items), self.last_span(tok))

    def st_input(self, tok: Token) -> A.Statement:
        channel = None
        if self.at_op("#"):
            channel = self.channel()
            self.expect_kind(K.COMMA, "','", "after the INPUT channel")
        targets = [self.assign_target()]
        while self.at_kind(K.COMMA):
            self.advance()
            targets.append(self.assign_target())
        return A.Input(channel, tuple(targets), self.last_span(tok))

    def st_close(self, tok: Token) -> A.Statement:
        channels: list[A.Expr] = []
        if not self.at_end():
            channels.append(self.channel())
            while self.at_kind(K.COMMA):
                self.advance()
                channels.append(self.channel())
        return A.Close(tuple(channels), self.last_span(tok))

    def st_com(self, tok: Token) -> A.Statement:
        port = None
        if self.at_kind(K.LPAREN):
            self.advance()
            port = self.expr()
            self.expect_kind(K.RPAREN, "')'", "after COM(n")
        stok = self.peek()
        sword = stok.text.upper() if stok.kind in WORD_KINDS else ""
        if sword not in ("ON", "OFF", "STOP"):
            raise self.fail(
                stok,
                f"Expected ON, OFF or STOP after COM, found {describe(stok)}",
                suggestion="Write COM ON, COM OFF or COM STOP.",
            )
        self.advance()
        return A.ComControl(port, A.ComState(sword), self.last_span(tok))
