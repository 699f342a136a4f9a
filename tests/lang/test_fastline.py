"""The fast path of the commonest line shapes (`melfa.lang.fastline`) builds the parser's
tree, field for field, or leaves the line to the parser.

Compared by ``repr`` as well as ``==``: equality leaves out the names as written (``Pa``),
which the checker's messages show.
"""

from __future__ import annotations

import random
import re

import pytest

from melfa.lang.fastline import read_line
from melfa.lang.lexer import tokenize
from melfa.lang.parser import Labels, parse, parse_line
from melfa.lang.reparse import FAST_FROM, LineCache
from tests.lang.test_golden import corpus

_LINES = re.compile(r"[^\r\n]*(?:\r\n|\r|\n)")


def parsed(piece: str, line: int) -> str:
    return repr(parse_line(tokenize(piece, line), Labels([])))


def pieces(text: str) -> list[str]:
    found = _LINES.findall(text)
    found.append(text[sum(map(len, found)) :])
    return found


def variants(piece: str) -> list[str]:
    """The line as written, and written otherwise: numbered, labelled, commented, lower
    case, with tabs, without spaces after commas, without its line end."""
    body = piece.rstrip("\r\n")
    return [
        piece,
        body + " ' c\n",
        "10 " + body + "\n",
        "*L1 " + body + "\r\n",
        "0042\t*Ab_1$ " + body + "\r",
        body.lower() + "\n",
        body.replace(" ", "\t") + "\n",
        "  " + body + "  ",
        body.replace(", ", ",") + "\n",
        body.replace(" ", "") + "\n",
    ]


def test_every_line_of_the_golden_corpus_reads_as_the_parser_reads_it() -> None:
    read = 0
    total = 0
    for text in corpus().values():
        for n, original in enumerate(pieces(text), 1):
            for piece in variants(original):
                total += 1
                fast = read_line(piece, n)
                if fast is not None:
                    read += 1
                    assert repr(fast) == parsed(piece, n), piece
    assert read > total // 3  # the fast path is taken, not only correct when it is


@pytest.mark.parametrize(
    "piece",
    [
        "MOV P1, -50\n",
        "10 MVS Pagafa\n",
        "mvs p1 , + .5 ' down\n",
        "HOPEN 1\n",
        "HCLOSE 1",
        "DLY 0.5\r\n",
        "OVRD 30\n",
        "ACCEL 50, 50\n",
        "HLT\n",
        "GOSUB *S0001\n",
        "GOTO 100\n",
        "RETURN\n",
        "RETURN 1\n",
        "END\n",
        "WEND\n",
        "NEXT MI\n",
        "NEXT\n",
        "MCOUNT = 0\n",
        "PATTERN% = -3\n",
        "PTMP.Z = 25.\n",
        "Pdest = Pbase\n",
        "*AGAFA ' pick\n",
        "' only a comment\n",
        "\n",
        "",
        "   \t ",
        "10\n",
        "IF M_IN(8) = 1 THEN *L\n",
        "IF MPILA <= 0 THEN *BUIDA\n",
        "if m1 =< -2 then gosub *s0001\n",
        "IF M1 THEN 100\n",
        "IF M1 <> M2 THEN\n",
        "FOR MFILA = 0 TO 2\n",
        "FOR MPECA = 0 TO 2 - MFILA STEP -1\n",
        "WHILE MCOUNT < 10\n",
        "MCOUNT = MCOUNT + 1\n",
        "MX = M1 \\ 2\n",
        "Pdest = Pbase + (0, 0, 25, 0, 0, 0)\n",
        "MVS Pagafa * (0, 0, -80, 0, 0, 0)\n",
        "MOV -P1, -M_IN(3)\n",
        "M1 = -(1, 2) * 3\n",
        "Pdest.X = Pbase.X + MDIAM * MPECA + MDIAM / 2 * MFILA\n",
        "WHILE M_IN(8) = 0 AND MCOUNT < 10\n",
        "M1 = 1 - 2 - 3 mod 2 XOR 1 OR M2 <> -P1.z\n",
        "MX = SIN(RAD(30)) * MDIAM + COS(RAD(60)) * MALT\n",
        "M1 = -ATN(M2 / (M3 + 1), 2) + FNA(M4, P1.X)\n",
        "P1 = (MX, MY + 5, 0, 0, -M_IN(M1 + 1), 0)\n",
        "MVS P03, -80 WTH M_OUT(17) = 1\n",
        "MOV P1 WTH M_OUT(MI + 16) = 1 DLY 0.5\n",
        "mov p1 wth hlt\n",
        "MVS P1, 10 WTH SKIP\n",
        "M_OUT(17) = 1 DLY 0.5\n",
        "P(MI).Z = P1.Z + 5\n",
        "IF M_IN(3) = 1 THEN M_OUT(25) = 1 ELSE HLT\n",
        "IF M1 = 1 THEN GOSUB *PICK ELSE *L2\n",
        "IF M1 THEN 100 ELSE 200\n",
        "IF M1 > 0 THEN MOV P1, -50 ELSE RETURN 1\n",
        "IF M1 THEN M2 = M2 + 1\n",
    ],
)
def test_the_common_shapes_are_read_here(piece: str) -> None:
    fast = read_line(piece, 7)
    assert fast is not None
    assert repr(fast) == parsed(piece, 7)


@pytest.mark.parametrize(
    "piece",
    [
        "REM a comment\n",  # REM is a comment word, not a name
        "REM# = 1\n",
        "MX# = 1\n",  # V's double suffix: the parser explains it
        "M1 = 1.0#\n",
        "M1 = 1E3\n",  # an exponent: the parser's
        "M1 = 10E\n",
        "10E3 MOV P1\n",  # a number the lexer reads as REAL, not a step number
        "10MOV P1\n",
        "*L# MOV P1\n",
        "*L.X = 1\n",
        "MOV P1 MOD 2\n",
        "MOV PLT\n",  # a keyword is never a name
        "MOV P1,\n",
        "MOV P1, P2, P3\n",
        "MOV\n",
        "MVS , -50\n",
        "MOV P1 WTH M_OUT(1) = 1\n",
        "HOPEN\n",  # missing argument: the parser says so
        "HOPEN 1, 2, 3, 4, 5\n",
        "DLY = 5\n",
        "M1 =< 5\n",
        "M1 == 5\n",
        "M1 = --5\n",
        "P1.Q = 5\n",
        "M_OUT(17) = 1\n",
        "M1 = 1 DLY 0.5\n",
        'M1 = "text"\n',
        'PRINT "a\'b"\n',
        "GOTO *L#\n",
        "GOTO 1.5\n",
        "GOTO L\n",
        "RETURN 1, 2\n",
        "END IF\n",
        "END SELECT\n",
        "WEND 1\n",
        "NEXT M1, M2\n",
        "NEXT IF\n",
        "M1 = 1 ' x\fy\n",
        "M1\f= 1\n",
        "Mà = 1\n",
        "WIHLE M1\n",
        "ElseIf M1 = 1\n",
        "M1 = P(1).X\n",
        "M1 = 5 .X\n",
        "M1 = P1.Q\n",
        "M1 = P1.X.Y\n",
        "M1 = 1 ^ 2 + 3\n",
        "M1 = -P1 ^ 2\n",
        "M1 = A AND$ B\n",
        "M1 = 2 ANDB\n",
        "M1 = NOT M2\n",
        "M1 = 2 ^ 3\n",
        "M1 = -2 ^ 2\n",
        "M1 = 1 << 2\n",
        "M1 = 1 MOD 2\n",
        "M1 = A = B\n",
        "M1 = 5 (1)\n",
        "M1 = SIN(1)\n",
        "M1 = FNA(1)\n",
        "M1 = M()\n",
        "M1 = (1)\n",
        "P1 = (1, 2)(7, 0)\n",
        "P1 = (1, , 2)\n",
        "P1 = ((1, 2))\n",
        "P1 = M_IN(1, M_IN(2))\n",
        "IF M1 = 1 THEN HOPEN 1\n",
        "IF M1 = 1 THEN *L ELSE *M\n",
        "IF M1 = 1 *L\n",
        "IF THEN *L\n",
        "IF M1 = 1 AND M2 = 2 THEN *L\n",
        "FOR M1 = 1\n",
        "FOR M1 = 1 STEP 2\n",
        "FOR M1 = 1 TO 3 STEP 1 STEP 2\n",
        "FOR M1 = 1 TO 3 STEP 1 4\n",
        "FOR IF = 1 TO 3\n",
        "FOR M.X = 1 TO 3\n",
        "FOR M1 =< 1 TO 3\n",
        "WHILE\n",
        "WHILE M1 < 10 AND M2\n",
        "M1 = SIN()\n",
        "M1 = SIN(1, )\n",
        "M1 = SIN 1\n",
        "M1 = PLT(1)\n",
        "M1 = SIN(1).X\n",
        "M1 = LEFT$(C1$, 2)\n",
        "M1 = " + "(" * 20 + "1" + ")" * 20 + "\n",
        "M1 = SIN(" * 20 + "1" + ")" * 20 + "\n",
        "Print(1) = 2\n",  # MELFA BASIC V: the parser says so
        "M_OUT(1) = 1 DLY\n",
        "M_OUT(1) = 1 HLT\n",
        "M_OUT(1)\n",
        "MOV P1 WTHIF M1 = 1, M_OUT(1) = 1\n",
        "MOV P1 TYPE 1, 0 WTH HLT\n",
        "MOV P1 WTH\n",
        "MOV P1 WTH HLT 1\n",
        "MOV P1 WTH HOPEN 1\n",
        "MOV P1, WTH HLT\n",
        "IF M1 THEN NEXT ELSE *L\n",  # NEXT reads on past ELSE: the parser's
        "IF M1 THEN IF M2 THEN *A ELSE *B\n",  # the ELSE is the inner IF's
        "IF M1 THEN HOPEN 1 ELSE\n",
        "IF M1 THEN ELSE *L\n",
        "IF M1 THEN *L ELSE *M ELSE *N\n",
        "IF M1 THEN *ELSE\n",
        "IF M1 THEN M2 = 1ELSE *L\n",
        "IF M1 THEN HOPEN 1 HCLOSE 1\n",
        "IF M1 THEN FOR M2 = 1 TO 3 ELSE *L\n",
        # Digits and letters of other scripts: the lexer reads 0-9 and A-Z only.
        "HOPEN \u0663\n",  # ARABIC-INDIC DIGIT THREE
        "M1 = \uff11\n",  # FULLWIDTH DIGIT ONE, as a Japanese input method types it
        "\uff11\uff10 MOV P1\n",
        "M1 = M_IN(\u0663)\n",
        "GOTO \u0663\n",
        "IF M1 THEN *L EL\u017fE *M\n",  # LATIN SMALL LETTER LONG S, 's' ignoring case
        "M1 = 1 MO\u212a 2\n",  # KELVIN SIGN
        "M1 = M2 \u017fOR M3\n",
    ],
)
def test_other_lines_are_left_to_the_parser_or_read_alike(piece: str) -> None:
    fast = read_line(piece, 3)
    assert fast is None or repr(fast) == parsed(piece, 3)


def test_a_big_text_read_through_the_cache_is_the_parsers_tree() -> None:
    """Every line of the corpus in one text, so many lines not seen that the cache reads
    them through the fast path (`melfa.lang.reparse.FAST_FROM`), numbered as written."""
    lines = [piece for text in corpus().values() for piece in pieces(text) if piece]
    text = "".join(p if p.endswith(("\n", "\r")) else p + "\n" for p in lines)
    assert len(lines) > 100 * FAST_FROM
    assert repr(LineCache().parse(text)) == repr(parse(text))


# Operands, operators and statement words, some of them near misses (REM, 1#, 10E3, <<, é).
_WORDS = "P1 m_in Pa% MX$ 5 0.5 .5 5. 10E3 1# REM rem PLT SIN FNA THEN TO STEP GOSUB *L *l2$ 100 AND mod Or XOR NOT ELSE".split()  # noqa: SIM905, E501
_MARKS = '+ - * / \\ ^ = <> >< <= =< >= => < > << >> , ( ) .X .z .Q # ; " &H1F _ é'.split()  # noqa: SIM905
_MARKS += [" ", "\t", "'", "\uff11", "\u0663", "\u017f"]
_HEADS = "MOV MVS HOPEN DLY OVRD IF FOR WHILE NEXT RETURN END WEND GOSUB GOTO M1 P1 P1.X *L 10 ' ACCEL HLT ELSE".split()  # noqa: SIM905, E501
_HEADS += ["", "10 *L"]


def test_near_misses_are_read_alike_or_left_to_the_parser() -> None:
    """20,000 seeded lines of statement words, operands and operators, many of them wrong:
    the fast path never raises, and what it reads is the parser's tree."""
    rng = random.Random(25)
    read = 0
    for _ in range(20_000):
        parts = [rng.choice(_HEADS)]
        for _ in range(rng.randint(0, 9)):
            parts.append(rng.choice(_WORDS) if rng.random() < 0.5 else rng.choice(_MARKS))
        piece = rng.choice([" ", " ", ""]).join(parts) + rng.choice(["\n", "\r\n", "", " ' c\n"])
        fast = read_line(piece, 3)
        if fast is not None:
            read += 1
            assert repr(fast) == parsed(piece, 3), piece
    assert read > 1_000


_NAMES = "M1 MX P1 Pa M_IN(3) M_OUT(17) P(1) P(MI+1) MI% C1$ P1.X PTMP.z M_IN(M1) Print m_out(2)"
_FUNCTIONS = "SIN COS RAD DEG ABS LEFT$ INT sqr ATN FNX MAX DIST PLT PTOJ".split()  # noqa: SIM905
_OPERATORS = ["+", "-", "*", "/", "=", "<>", "AND", "OR", "MOD", "^", "\\"]
_BRANCHES = ["HLT", "END", "RETURN", "SKIP", "ELSE", "NEXT", "WEND", "BREAK", "HOPEN 1", "DLY 0.5"]


def _expression(rng: random.Random, depth: int = 0) -> str:
    r = rng.random()
    if depth > 3 or r < 0.3:
        return rng.choice([*_NAMES.split(), "1", "0.5", "-2", ".5", "&H1F", "1E3", "2#"])
    if r < 0.5:
        args = ", ".join(_expression(rng, depth + 1) for _ in range(rng.choice((0, 1, 1, 2))))
        return f"{rng.choice(_FUNCTIONS)}({args})"
    if r < 0.8:
        op = rng.choice(_OPERATORS)
        return f"{_expression(rng, depth + 1)} {op} {_expression(rng, depth + 1)}"
    if r < 0.9:
        return "-" + _expression(rng, depth + 1)
    items = ", ".join(_expression(rng, depth + 1) for _ in range(rng.choice((1, 2, 6))))
    return f"({items})"


def _statement(rng: random.Random, depth: int = 0) -> str:
    r = rng.random()
    if r < 0.25:
        pulse = f" DLY {_expression(rng)}" if rng.random() < 0.3 else ""
        return f"{rng.choice(_NAMES.split())} = {_expression(rng)}{pulse}"
    if r < 0.4:
        close = f", {_expression(rng)}" if rng.random() < 0.5 else ""
        action = rng.choice(["HLT", "SKIP", "M_OUT(1) = 1", "M_OUT(2) = 0 DLY 0.1"])
        tail = f" WTH {action}" if rng.random() < 0.6 else ""
        return f"{rng.choice(['MOV', 'MVS', 'mov'])} {_expression(rng)}{close}{tail}"
    if r < 0.5:
        return rng.choice(_BRANCHES)
    if r < 0.6:
        return f"{rng.choice(['GOTO', 'GOSUB'])} {rng.choice(['*L', '100', '*L#', 'L'])}"
    if r < 0.7:
        return rng.choice(["*L", "100", "*Loop2", "10"])
    if r < 0.9 and depth < 2:
        line = f"IF {_expression(rng)} THEN {_statement(rng, depth + 1)}"
        if rng.random() < 0.6:
            line += f" ELSE {_statement(rng, depth + 1)}"
        return line
    return f"{rng.choice(_NAMES.split())} = {_expression(rng)}"


def _mutated(rng: random.Random, text: str) -> str:
    marks = [*" ,()=*'+-.#$\t", "ELSE", "THEN", "WTH", "DLY"]
    for _ in range(rng.choice((0, 0, 1, 2))):
        i = rng.randrange(len(text) + 1)
        r = rng.random()
        if r < 0.4:
            text = text[:i] + text[i + 1 :]
        elif r < 0.8:
            text = text[:i] + rng.choice(marks) + text[i:]
        else:
            text = text.upper() if rng.random() < 0.5 else text.lower()
    return text


def test_statements_built_of_calls_branches_and_move_actions_read_alike() -> None:
    """20,000 seeded statements of calls, IF…THEN…ELSE branches, WTH actions and indexed
    targets, a third of them with a character removed or added: what the fast path reads is
    the parser's tree (820,000 were compared while writing it: none differed)."""
    rng = random.Random(2025)
    read = 0
    for _ in range(20_000):
        piece = _mutated(rng, _statement(rng)) + rng.choice(["\n", "", " ' c\n"])
        fast = read_line(piece, 3)
        if fast is not None:
            read += 1
            assert repr(fast) == parsed(piece, 3), piece
    assert read > 4_000
