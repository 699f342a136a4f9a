"""The statements that decide which step runs next: GOTO, GOSUB, ON … GOTO/GOSUB, ON COM,
RETURN, IF … THEN … ELSE (resuming at THEN after a bad condition), the block words, FOR/NEXT,
WHILE/WEND, SELECT/CASE, END, WAIT, FPRM and RESET ERR.

One family of the line parser (`melfa.lang.parser` dispatches to the ``st_`` methods). An IF's
branch may be any statement: it is read by the line parser's `statement`.
"""

from __future__ import annotations

from melfa.lang import ast as A  # noqa: N812  (short alias: the parser builds many nodes)
from melfa.lang.grammar import BINARY
from melfa.lang.parse_cursor import END_KINDS, Fail, K, describe
from melfa.lang.parse_expr import ExprParser
from melfa.lang.tokens import STATEMENT_KEYWORDS, Token


class FlowStatements(ExprParser):
    """Jumps, IF, loops, SELECT CASE and the other flow words."""

    def statement(self, stop: frozenset[str] = frozenset()) -> A.Statement:
        """Any statement (an IF's branch): `melfa.lang.parser`'s line parser reads it."""
        raise NotImplementedError

    # flow ----------------------------------------------------------------------------

    def st_goto(self, tok: Token) -> A.Statement:
        target = self.target(f"after {tok.text.upper()}")
        if tok.text.upper() == "GOTO":
            return A.Goto(target, self.last_span(tok))
        return A.Gosub(target, self.last_span(tok))

    def st_on(self, tok: Token) -> A.Statement:
        if self.at_word("COM"):
            self.advance()
            port = None
            if self.at_kind(K.LPAREN):
                self.advance()
                port = self.expr()
                self.expect_kind(K.RPAREN, "')'", "after ON COM(n")
            self.expect_word("GOSUB", "after ON COM")
            target = self.target("after ON COM … GOSUB")
            return A.OnCom(port, target, self.last_span(tok))
        selector = self.expr()
        if self.at_word("GOTO"):
            kind = A.JumpKind.GOTO
        elif self.at_word("GOSUB"):
            kind = A.JumpKind.GOSUB
        else:
            nxt = self.peek()
            raise self.fail(
                nxt,
                f"Expected GOTO or GOSUB after ON's value, found {describe(nxt)}",
                suggestion="Write GOTO or GOSUB after the value, e.g. ON M1 GOTO *A, *B.",
            )
        self.advance()
        targets = [self.target(f"after ON … {kind.value}")]
        while self.at_kind(K.COMMA):
            self.advance()
            targets.append(self.target("in the ON list"))
        return A.OnJump(selector, kind, tuple(targets), self.last_span(tok))

    def st_return(self, tok: Token) -> A.Statement:
        mode = None if self.at_end() or self.at_word("ELSE") else self.expr()
        return A.Return(mode, self.last_span(tok))

    def branch(self, stop: frozenset[str]) -> A.JumpTarget | A.Statement:
        tok = self.toks[self.i]
        if tok.kind is K.INTEGER or tok.kind is K.LABEL:
            return self.target("")
        return self.statement(stop)

    def st_if(self, tok: Token) -> A.Statement:
        toks = self.toks
        cond_start = self.toks[self.i]
        condition: A.Expr
        try:
            if self.at_end() or self.at_word("THEN"):
                raise self.fail(
                    self.peek(),
                    "IF needs a condition",
                    "missing-argument",
                    "Add a condition, e.g. IF M1 = 1 THEN *LOOP.",
                )
            condition = self.expr()
        except Fail as failure:
            self.depth = 0
            # Resume at THEN if the line has one; otherwise the whole IF is invalid.
            j = self.i
            while toks[j].kind not in END_KINDS and not (
                toks[j].kind is K.KEYWORD and toks[j].text.upper() == "THEN"
            ):
                j += 1
            if toks[j].kind in END_KINDS:
                raise
            self.i = j
            last = toks[j - 1] if j > 0 else cond_start
            condition = A.InvalidExpr(
                failure.issue,
                A.Span(cond_start.line, cond_start.column, last.line, last.end_column),
            )
        then: A.JumpTarget | A.Statement | None
        if self.at_word("THEN"):
            self.advance()
            if self.at_end():
                return A.If(condition, None, None, self.last_span(tok))
        else:
            nxt = self.peek()
            found = describe(nxt)
            message = f"Expected THEN after IF condition and instead found {found}"
            cond_text = "".join(t.prefix + t.text for t in toks[toks.index(cond_start) : self.i])
            rest = " …" if nxt.kind in END_KINDS else f" {nxt.text} …"
            hint = f"Add THEN after the condition: IF {cond_text.strip()} THEN{rest}"
            if not (
                nxt.kind is K.KEYWORD and nxt.text.upper() in STATEMENT_KEYWORDS
            ) and nxt.kind not in (K.INTEGER, K.LABEL):
                raise self.fail(nxt, message, "expected-then", hint, replacement="THEN")
            # The branch is readable: report the missing THEN and parse on.
            self.issue(nxt, message, "expected-then", hint, replacement="THEN")
        then = self.branch(frozenset({"ELSE"}))
        else_: A.JumpTarget | A.Statement | None = None
        if self.at_word("ELSE"):
            self.advance()
            if self.at_end():
                raise self.fail(
                    self.peek(),
                    "ELSE needs a line number, *label or statement",
                    suggestion="Add where to go after ELSE, e.g. ELSE *OTHER.",
                )
            else_ = self.branch(frozenset())
        return A.If(condition, then, else_, self.last_span(tok))

    def st_else(self, tok: Token) -> A.Statement:
        return A.Else(self.last_span(tok))

    def st_endif(self, tok: Token) -> A.Statement:
        return A.EndIf(self.last_span(tok))

    def st_for(self, tok: Token) -> A.Statement:
        counter = self.name("after FOR")
        self.expect_op("=", "after the FOR counter")
        start = self.expr()
        self.expect_word("TO", "after the FOR start value")
        end = self.expr()
        step = None
        if self.at_word("STEP"):
            self.advance()
            step = self.expr()
        return A.For(counter, start, end, step, self.last_span(tok))

    def st_next(self, tok: Token) -> A.Statement:
        counters: list[A.Name] = []
        if not self.at_end():
            counters.append(self.name("after NEXT"))
            while self.at_kind(K.COMMA):
                self.advance()
                counters.append(self.name("in the NEXT list"))
        return A.Next(tuple(counters), self.last_span(tok))

    def st_while(self, tok: Token) -> A.Statement:
        if self.at_end():
            raise self.fail(
                self.peek(),
                "WHILE needs a condition",
                "missing-argument",
                "Add a condition, e.g. WHILE M1 < 10.",
            )
        return A.While(self.expr(), self.last_span(tok))

    def st_wend(self, tok: Token) -> A.Statement:
        return A.Wend(self.last_span(tok))

    def st_select(self, tok: Token) -> A.Statement:
        if self.at_end():
            raise self.fail(
                self.peek(),
                "SELECT needs a value to compare",
                "missing-argument",
                "Add the value to compare, e.g. SELECT M1.",
            )
        return A.Select(self.expr(), self.last_span(tok))

    def st_case(self, tok: Token) -> A.Statement:
        if self.at_word("IS"):
            self.advance()
            op_tok = self.peek()
            entry = BINARY.get(op_tok.text) if op_tok.kind is K.OP else None
            if entry is None or not entry[1].is_comparison:
                raise self.fail(
                    op_tok,
                    f"Expected a comparison after CASE IS, found {describe(op_tok)}",
                    suggestion="Write a comparison after IS, e.g. CASE IS >= 3.",
                )
            self.advance()
            value = self.expr()
            return A.Case(A.CaseKind.IS, value, None, entry[1], self.last_span(tok))
        if self.at_end():
            raise self.fail(
                self.peek(), "CASE needs a value", "missing-argument", "Add a value, e.g. CASE 1."
            )
        value = self.expr()
        if self.at_word("TO"):
            self.advance()
            high = self.expr()
            return A.Case(A.CaseKind.RANGE, value, high, None, self.last_span(tok))
        return A.Case(A.CaseKind.VALUE, value, None, None, self.last_span(tok))

    def st_break(self, tok: Token) -> A.Statement:
        return A.Break(self.last_span(tok))

    def st_default(self, tok: Token) -> A.Statement:
        return A.Default(self.last_span(tok))

    def st_end(self, tok: Token) -> A.Statement:
        if self.at_word("SELECT"):
            self.advance()
            return A.EndSelect(self.last_span(tok))
        if self.at_word("IF"):
            raise self.fail(
                tok,
                "Invalid statement. Did you mean ENDIF instead of END IF?",
                "unknown-statement",
                "Write ENDIF as one word.",
                replacement="ENDIF",
            )
        return A.Command(A.CommandKind.END, (), self.last_span(tok))

    def st_wait(self, tok: Token) -> A.Statement:
        if self.at_end():
            raise self.fail(
                self.peek(),
                "WAIT needs a condition",
                "missing-argument",
                "Add a condition, e.g. WAIT M_IN(1) = 1.",
            )
        return A.Wait(self.expr(), self.last_span(tok))

    def st_fprm(self, tok: Token) -> A.Statement:
        params = [self.name("after FPRM")]
        while self.at_kind(K.COMMA):
            self.advance()
            params.append(self.name("in the FPRM list"))
        return A.Fprm(tuple(params), self.last_span(tok))

    def st_reset(self, tok: Token) -> A.Statement:
        self.expect_word("ERR", "after RESET")
        return A.Command(A.CommandKind.RESET_ERR, (), self.last_span(tok))
