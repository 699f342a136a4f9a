"""The one model of MELFA BASIC IV's knowledge: statements, functions, system variables,
limits, dialects.

Everything that both the checker (`melfa.lang.check`) and the simulator's interpreter
(`melfa.sim.interp`) need to know about the language lives here, once: the statement
words; which built-in functions exist, how many arguments of which kind each takes and what
it gives back; which status (system) variables exist, their type, whether they take an
index and whether a program may assign them; the controller's limits. The interpreter
keeps only run-time behaviour (how SIN computes, where M_IN reads). Section numbers (§)
refer to ``../shared/docs/melfa-basic-iv.md``.

Dialects: the CR2B-574 runs MELFA BASIC IV. `V_CONSTRUCTS` lists what MELFA BASIC V
(newer controllers, most programs found online) adds, so the checker can say "this is V"
once per construct. A V dialect could later be a second `Dialect` whose model accepts those
constructs; today only `Dialect.IV` exists and `foreign_constructs` gives V's for it.
"""

from __future__ import annotations

import enum
from collections.abc import Mapping

from melfa.lang.record import Record


class Dialect(enum.Enum):
    """The language a program is checked against. Only IV is modelled (the CR2B-574's)."""

    IV = "MELFA BASIC IV"


class Kind(enum.Enum):
    """The kind of a value (§3): what static typing can tell about an expression."""

    NUM = "number"
    STR = "string"
    POS = "position"
    JNT = "joint"

    __hash__ = object.__hash__  # identity hashing: members are singletons (hot loops)


# --------------------------------------------------------------------------- statements §4


def _words(text: str) -> frozenset[str]:
    return frozenset(text.split())


#: The words that start a statement (§4); the parser dispatches on them, the typo checker
#: suggests only these.
STATEMENTS: frozenset[str] = _words(
    """
    MOV MVS MVR MVR2 MVR3 MVC MVA
    OVRD JOVRD SPD ACCEL CNT FINE PREC OADL LOADSET TORQ JRC
    HOPEN HCLOSE SERVO TOOL BASE
    GOTO GOSUB ON RETURN IF ELSE ENDIF FOR NEXT WHILE WEND
    SELECT CASE BREAK DEFAULT END HLT DLY WAIT ERROR SKIP CALLP FPRM
    DEF DIM ACT OPEN PRINT INPUT CLOSE COM
    XLOAD XRUN XSTP XRST XCLR PRIORITY GETM RELM
    CMP CMPG CLR RESET CHRSRCH REM
    """
)

#: Reserved words that only appear inside statements. `BIT`…`DWORD` are the DEF IO types
#: (`DEF IO MSENSOR = BIT, 900`) [S1 DEF IO]; DWORD is V's.
SECONDARY_WORDS: frozenset[str] = _words(
    """
    THEN TO STEP IS TYPE WTH WTHIF AND OR NOT XOR MOD
    INTE FLOAT DOUBLE CHAR POS JNT IO PLT ARCH AS OFF ERR OUTPUT APPEND
    BIT BYTE WORD INTEGER DWORD
    """
)


# ------------------------------------------------------------------------------ limits §8

MAX_LINE_LENGTH = 127  # characters a step, without the terminator (§1), L4210
MAX_DEF_LENGTH = 123  # a DEF POS/JNT/INTE/FLOAT/DOUBLE/CHAR list, from DEF on (§4.6)
MAX_NAME_LENGTH = 8  # variable names, labels, DEF FN names (§1, §2.1), L4300
MAX_LINE_NUMBER = 32767  # (§1), L4420
MAX_ON_TARGETS = 32  # ON … GOTO/GOSUB destinations, L3251
MAX_DIMENSIONS = 3  # DIM name(a, b, c) (§3)
MAX_DIM_SIZE = 999  # DIM sizes are constants 1…999 (§3)
MIN_DLY = 0.05  # seconds, the IV minimum (§4.5)
MAX_LOOP_DEPTH = 16  # FOR/WHILE nesting (§4.5), L3240
MAX_IF_DEPTH = 8  # block IF nesting, L3253
MAX_GOSUB_DEPTH = 800  # nested GOSUBs, about 800 (§4.5)
MAX_FN_ARGS = 16  # DEF FN dummy arguments (§4.6)
MAX_POSITION_ELEMENTS = 8  # X,Y,Z,A,B,C,L1,L2 (§2.2)
MAX_JOINT_ELEMENTS = 8  # J1…J8 (§2.2)
MIN_POSITION_ELEMENTS = 6  # a points file gives at least X…C / J1…J6 (§12)
MAX_FL1 = 7  # three bits R/L, A/B, N/F (§12)

#: Constant arguments with a range, by statement word: (low, high, what) (§4.2–§4.6).
RANGES: Mapping[str, tuple[float, float, str]] = {
    # 1…100 % is the recommended range, but any value above 0 runs (resolution 0.1 %):
    # "if 0 or a value over 100 is set, an error will occur" [S1 OVRD, JOVRD].
    "OVRD": (0, 100, "OVRD takes more than 0 and up to 100 (%)"),
    "JOVRD": (0, 100, "JOVRD takes more than 0 and up to 100 (%)"),
    "HOPEN": (1, 8, "Hand numbers are 1 to 8"),
    "HCLOSE": (1, 8, "Hand numbers are 1 to 8"),
    "ERROR": (9000, 9299, "User error numbers are 9000 to 9299"),
    "PLT": (1, 8, "Pallet numbers are 1 to 8"),
    "ACT": (1, 8, "Interrupt numbers (DEF ACT priorities) are 1 to 8"),
    "RETURN": (0, 1, "An interrupt routine returns with RETURN 0 or RETURN 1"),
}
#: Range words whose low end is itself refused (OVRD 0 is an error, OVRD 0.5 is not).
OPEN_LOW: frozenset[str] = frozenset({"OVRD", "JOVRD"})


# --------------------------------------------------------------------------- functions §5


class Function(Record):
    """A built-in function: argument kinds (None: any kind), how many, what it gives.

    `params` lists the kind of each argument in order; when more arguments are allowed than
    listed (MAX, SETPOS) the last kind repeats. `result` None means the kind depends on the
    arguments.
    """

    name: str
    params: tuple[Kind | None, ...]
    min_args: int
    max_args: int
    result: Kind | None
    section: str = "§5"

    def param(self, index: int) -> Kind | None:
        """The kind argument `index` (0-based) must have, None when any kind will do."""
        if not self.params:
            return None
        return self.params[min(index, len(self.params) - 1)]

    @property
    def usage(self) -> str:
        """How it is called, for messages: ``MID$(string, number[, number])``."""
        words = []
        for i in range(min(self.max_args, max(self.min_args, len(self.params)))):
            kind = self.param(i)
            words.append(kind.value if kind is not None else "value")
        shown = ", ".join(words[: self.min_args])
        if len(words) > self.min_args:
            rest = ", ".join(words[self.min_args :])
            shown = f"{shown}[, {rest}]" if shown else f"[{rest}]"
        if self.max_args > len(words):
            shown += ", …"
        return f"{self.name}({shown})"

    @property
    def arity_text(self) -> str:
        """How many arguments, in words: "1", "2 or 3", "1 to 8"."""
        lo, hi = self.min_args, self.max_args
        if lo == hi:
            return str(lo)
        return f"{lo} or {hi}" if hi == lo + 1 else f"{lo} to {hi}"


N, S, P, J = Kind.NUM, Kind.STR, Kind.POS, Kind.JNT


def _fn(name: str, params: tuple[Kind | None, ...], result: Kind | None,
        lo: int | None = None, hi: int | None = None) -> Function:  # fmt: skip
    count = len(params)
    return Function(name, params, count if lo is None else lo, count if hi is None else hi, result)


#: Every built-in function of IV (the COSIMIR list plus SETJNT/SETPOS, §5).
FUNCTIONS: Mapping[str, Function] = {
    f.name: f
    for f in (
        # numeric
        _fn("ABS", (N,), N),
        _fn("ASC", (S,), N),
        _fn("CINT", (N,), N),
        _fn("CKSUM", (S, N, N), N),  # (inferred) CKSUM(string, start, end) from the V manual
        _fn("CVD", (S,), N),
        _fn("CVI", (S,), N),
        _fn("CVS", (S,), N),
        _fn("DEG", (N,), N),
        _fn("EXP", (N,), N),
        _fn("FIX", (N,), N),
        _fn("INT", (N,), N),
        _fn("LEN", (S,), N),
        _fn("LN", (N,), N),
        _fn("LOG", (N,), N),
        _fn("MAX", (N,), N, 1, 32),
        _fn("MIN", (N,), N, 1, 32),
        _fn("RAD", (N,), N),
        _fn("RND", (N,), N),
        _fn("SGN", (N,), N),
        _fn("SQR", (N,), N),
        _fn("STRPOS", (S, S), N),
        _fn("VAL", (S,), N),
        # trig (radians)
        _fn("SIN", (N,), N),
        _fn("COS", (N,), N),
        _fn("TAN", (N,), N),
        _fn("ATN", (N,), N),
        _fn("ATN2", (N, N), N),
        # strings
        _fn("BIN$", (N, N), S, 1, 2),
        _fn("CHR$", (N,), S),
        _fn("HEX$", (N, N), S, 1, 2),
        _fn("LEFT$", (S, N), S),
        _fn("MID$", (S, N, N), S, 2, 3),
        _fn("MIRROR$", (S,), S),
        _fn("MKI$", (N,), S),
        _fn("MKS$", (N,), S),
        _fn("MKD$", (N,), S),
        _fn("RIGHT$", (S, N), S),
        _fn("STR$", (N,), S),
        # positions
        _fn("DIST", (P, P), N),
        _fn("FRAM", (P, P, P), P),
        _fn("INV", (P,), P),
        _fn("JTOP", (J,), P),
        _fn("PTOJ", (P,), J),
        _fn("POSCQ", (None,), N),  # a position or a joint position
        _fn("POSMID", (P, P, N, N), P, 2, 4),
        _fn("ALIGN", (P,), P),
        _fn("ZONE", (P, P, P), N),
        _fn("ZONE2", (P, P, P, N), N, 3, 4),  # (inferred) the radius from the V manual
        _fn("CALARC", (P, P, P), N, 3, 16),  # (inferred) more arguments in V; not checked
        _fn("RDFL1", (P, N), S),
        _fn("SETFL1", (P, None), P),  # letters "RAN" or a number
        _fn("RDFL2", (P, N), N),
        _fn("SETFL2", (P, N, N), P),
        _fn("SETJNT", (N,), J, 1, 8),
        _fn("SETPOS", (N,), P, 1, 8),
    )
}


# ---------------------------------------------------------------------- system variables §6


class Index(enum.Enum):
    """Whether a system variable takes a number in parentheses: ``M_IN(8)``, ``P_CURR(1)``."""

    NONE = "none"
    OPTIONAL = "optional"  # a mechanism or slot number: P_CURR(1), M_RUN(2)
    REQUIRED = "required"  # an I/O, hand or timer number: M_IN(8)


class SystemVariable(Record):
    """A robot status variable (§6): its kind, index and whether a program may assign it."""

    name: str
    kind: Kind
    assignable: bool
    index: Index = Index.OPTIONAL
    io_width: int = 0  # bits read or written from the index on (M_IN8: 8); 0 when not I/O


def _sv(name: str, assignable: bool = False, index: Index = Index.OPTIONAL,
        io_width: int = 0) -> SystemVariable:  # fmt: skip
    kind = {"P": Kind.POS, "J": Kind.JNT, "C": Kind.STR}.get(name[0], Kind.NUM)
    return SystemVariable(name, kind, assignable, index, io_width)


_R = Index.REQUIRED

#: The status variables of IV (§6, [S2e]); names with ``_`` as 2nd character that are not
#: here are the program's own external (global) variables (``M_01``, ``P_01``).
SYSTEM_VARIABLES: Mapping[str, SystemVariable] = {
    v.name: v
    for v in (
        _sv("P_CURR"),
        _sv("J_CURR"),
        _sv("P_TOOL", assignable=True),
        _sv("P_BASE", assignable=True),
        _sv("P_NTOOL"),
        _sv("P_NBASE"),
        _sv("P_SAFE"),
        _sv("M_TOOL", assignable=True),
        _sv("M_IN", index=_R, io_width=1),
        _sv("M_INB", index=_R, io_width=8),
        _sv("M_IN8", index=_R, io_width=8),
        _sv("M_INW", index=_R, io_width=16),
        _sv("M_IN16", index=_R, io_width=16),
        _sv("M_IN32", index=_R, io_width=32),
        _sv("M_OUT", assignable=True, index=_R, io_width=1),
        _sv("M_OUTB", assignable=True, index=_R, io_width=8),
        _sv("M_OUT8", assignable=True, index=_R, io_width=8),
        _sv("M_OUTW", assignable=True, index=_R, io_width=16),
        _sv("M_OUT16", assignable=True, index=_R, io_width=16),
        _sv("M_OUT32", assignable=True, index=_R, io_width=32),
        _sv("M_DIN", index=_R),
        _sv("M_DOUT", assignable=True, index=_R),
        _sv("M_HNDCQ", index=_R),
        _sv("M_TIMER", assignable=True, index=_R),
        _sv("M_SVO"),
        _sv("M_RUN"),
        _sv("M_WAI"),
        _sv("M_PSA"),
        _sv("M_ERR"),
        _sv("M_ERRNO"),
        _sv("M_SKIPCQ"),
        _sv("M_OVRD", assignable=True),
        _sv("M_JOVRD", assignable=True),
        _sv("M_SPD", assignable=True),
        _sv("M_OPOVRD"),
        _sv("M_NOVRD"),
        _sv("M_NJOVRD"),
        _sv("M_NSPD", assignable=True),
        _sv("M_RSPD"),
        _sv("M_MRATIO"),
        _sv("C_TIME"),
        _sv("C_DATE"),
    )
}


def is_external(name: str) -> bool:
    """A name with ``_`` as its 2nd character: a system variable or an external variable."""
    return len(name) > 1 and name[1] == "_"


# ------------------------------------------------------------------------------ dialects


class Construct(Record):
    """A construct of another dialect: what it is and how to write it in IV (None: no way)."""

    word: str
    what: str
    in_iv: str | None


#: What MELFA BASIC V has and IV does not, keyed by the word that starts it (§0, §4).
V_CONSTRUCTS: Mapping[str, Construct] = {
    c.word: c
    for c in (
        Construct(
            "ELSEIF",
            "ElseIf",
            "Write ELSE, then a new IF … THEN block inside it with its own ENDIF.",
        ),
        Construct(
            "CONST",
            "Const",
            "Leave out Const: declare with DEF (DEF INTE NAME) and assign the value on its "
            "own line (NAME = 12).",
        ),
        Construct("FUNCTION", "Function … FEnd", "Use a subroutine (GOSUB … RETURN) or DEF FN."),
        Construct("FEND", "Function … FEnd", "Use a subroutine (GOSUB … RETURN) or DEF FN."),
        Construct("INCLUDE", "Include", "Copy the lines into this program, or call it with CALLP."),
        Construct("FSC", "Fsc (force sensor control)", None),
        Construct("FSCTRL", "FsCTrl (force sensor control)", None),
        Construct("MVTUNE", "MvTune", None),
        Construct("MVSPL", "MvSpl (spline moves)", None),
        Construct("EMVR2", "EMvr2", "Use MVR2."),
        Construct("EMVS", "EMvs", "Use MVS."),
        Construct("EMOV", "EMov", "Use MOV."),
        Construct("COLCHK", "ColChk (collision detection)", None),
        Construct("COLLVL", "ColLvl (collision detection)", None),
        Construct("HANDSPD", "HandSpd", None),
        # Vision sensors (network vision, In-Sight/COGNEX): V's NV… and EB… commands.
        Construct("NVOPEN", "NVOpen (network vision sensor)", None),
        Construct("NVCLOSE", "NVClose (network vision sensor)", None),
        Construct("NVLOAD", "NVLoad (network vision sensor)", None),
        Construct("NVRUN", "NVRun (network vision sensor)", None),
        Construct("NVPST", "NVPst (network vision sensor)", None),
        Construct("NVIN", "NVIn (network vision sensor)", None),
        Construct("NVTRG", "NVTrg (network vision sensor)", None),
        Construct("EBREAD", "EBRead (vision sensor)", None),
        Construct("EBWRITE", "EBWrite (vision sensor)", None),
        # Force sensor (the force-sense option's samples, melfa-basic-iv §11 item 16).
        Construct("FSLOG", "FsLog (force sensor log)", None),
        Construct("FSOUTLOG", "FsOutLog (force sensor log)", None),
        Construct("FSGCHG", "FsGChg (force sensor control)", None),
        Construct("FSCTRG", "FsCTrg (force sensor control)", None),
        Construct("SETMOTRG", "SetMoTrg (force sensor trigger)", None),
        Construct("MXT", "Mxt (real-time external control)", None),
    )
}

#: DEF types only MELFA BASIC V has (``Def Long``, ``Def MoTrg``): word -> construct.
V_DEF_TYPES: Mapping[str, Construct] = {
    c.word: c
    for c in (
        Construct("LONG", "Def Long", "Declare it with DEF DOUBLE (or DEF INTE up to 32767)."),
        Construct("MOTRG", "Def MoTrg (force sensor trigger)", None),
    )
}

#: Status variables only MELFA BASIC V has: name -> the IV way to write it (None: no way).
#: Names with these prefixes are V's force-sensor variables (P_FsCurD, M_FsLmtS…).
V_SYSTEM_VARIABLES: Mapping[str, str | None] = {
    "M_PI": "Write the number, 3.14159265, or compute it as 4 * ATN(1).",
    "M_EXP": "Compute it as EXP(1).",
    "M_G": "Write the number, 9.80665.",
    "M_ON": "Write 1.",
    "M_OFF": "Write 0.",
    "P_ZERO": "Write the constant (0, 0, 0, 0, 0, 0)(0, 0).",
    "C_COM": None,
    "C_PRG": None,
    "C_MAKER": None,
    "C_MECHA": None,
    "C_USER": None,
    "M_UAR": None,
    "M_MODE": None,
    "M_CYS": None,
    "M_LINE": None,
    "M_ERRLVL": None,
    "M_NVOPEN": None,
    "M_NVS1": None,
    "M_MOTRG": None,
    "P_FBC": None,
    "J_FBC": None,
    "J_ECURR": None,
    "M_LDFACT": None,
    "M_BTIME": None,
    "M_COLSTS": None,
    "P_COLDIR": None,
}
V_SYSTEM_PREFIXES = ("P_FS", "M_FS", "J_FS")


def foreign_constructs(dialect: Dialect = Dialect.IV) -> Mapping[str, Construct]:
    """The constructs of other dialects a program written for `dialect` must not use."""
    return V_CONSTRUCTS if dialect is Dialect.IV else {}
