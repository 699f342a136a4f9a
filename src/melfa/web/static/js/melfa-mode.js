// MELFA BASIC IV for Ace: highlighting, bracket matching (paren tokens), block auto-indent
// and auto-outdent, and a calm light theme. Word lists follow melfa.lang.tokens; the
// checker on the server stays the authority on what is valid.

const ace = window.ace;
const oop = ace.require("ace/lib/oop");
const TextMode = ace.require("ace/mode/text").Mode;
const TextHighlightRules = ace.require("ace/mode/text_highlight_rules").TextHighlightRules;

const STATEMENTS =
  "MOV MVS MVR MVR2 MVR3 MVC MVA OVRD JOVRD SPD ACCEL CNT FINE PREC OADL LOADSET TORQ JRC " +
  "HOPEN HCLOSE SERVO TOOL BASE GOTO GOSUB ON RETURN IF ELSE ENDIF FOR NEXT WHILE WEND " +
  "SELECT CASE BREAK DEFAULT END HLT DLY WAIT ERROR SKIP CALLP FPRM DEF DIM ACT OPEN PRINT " +
  "INPUT CLOSE COM XLOAD XRUN XSTP XRST XCLR PRIORITY GETM RELM CMP CMPG CLR RESET CHRSRCH";
const SECONDARY =
  "THEN TO STEP IS TYPE WTH WTHIF AND OR NOT XOR MOD INTE FLOAT DOUBLE CHAR POS JNT IO PLT " +
  "ARCH AS OFF ERR OUTPUT APPEND BIT BYTE WORD INTEGER DWORD";
const FUNCTIONS =
  "ABS ASC CINT CKSUM CVD CVI CVS DEG EXP FIX INT LEN LN LOG MAX MIN RAD RND SGN SQR STRPOS " +
  "VAL SIN COS TAN ATN ATN2 BIN$ CHR$ HEX$ LEFT$ MID$ MIRROR$ MKI$ MKS$ MKD$ RIGHT$ STR$ DIST " +
  "FRAM INV JTOP PTOJ POSCQ POSMID ALIGN ZONE ZONE2 CALARC RDFL1 SETFL1 RDFL2 SETFL2 SETJNT SETPOS";

const wordSet = (text) => new Set(text.split(/\s+/));
const STATEMENT_SET = wordSet(STATEMENTS);
const SECONDARY_SET = wordSet(SECONDARY);
const FUNCTION_SET = wordSet(FUNCTIONS);

function MelfaHighlightRules() {
  const word = (value) => {
    const upper = value.toUpperCase();
    if (upper === "ON" || upper === "OFF") return "constant.language";
    if (STATEMENT_SET.has(upper) || SECONDARY_SET.has(upper)) return "keyword";
    if (FUNCTION_SET.has(upper)) return "support.function";
    return "identifier";
  };
  this.$rules = {
    start: [
      { token: "constant.other.linenumber", regex: /^\s*\d+(?=\s|$)/ },
      { token: "comment", regex: /'.*$/ },
      { token: "comment", regex: /\b[Rr][Ee][Mm]\b.*$/ },
      { token: "entity.name.label", regex: /\*[A-Za-z][A-Za-z0-9_]*/ },
      { token: "string", regex: /"[^"]*"?/ },
      { token: "constant.numeric", regex: /&[Hh][0-9A-Fa-f]+|&[Bb][01]+/ },
      { token: "constant.numeric", regex: /(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?/ },
      // System variables: P_CURR, J_CURR, M_IN, M_OUT, M_TIMER, C_TIME, ... (and element access).
      { token: "variable.language", regex: /\b[PJMC]_[A-Za-z0-9_]+\$?/ },
      // Position / joint elements after a dot: P1.X, J1.J3, P1.FL1.
      { token: "variable.parameter", regex: /\.(?:[Ff][Ll][12]|[Jj][1-8]|[Ll][12]|[XYZABCxyzabc])\b/ },
      { token: word, regex: /[A-Za-z][A-Za-z0-9_]*\$?/ },
      { token: "keyword.operator", regex: /<>|><|<=|=<|>=|=>|[-+*/\\^=<>]/ },
      { token: "paren.lparen", regex: /[(]/ },
      { token: "paren.rparen", regex: /[)]/ },
      { token: "punctuation", regex: /,/ },
      { token: "text", regex: /\s+/ },
    ],
  };
  this.normalizeRules();
  // Ctrl+Space completes these (Ace's keyword completer reads $keywordList).
  this.$keywordList = [...STATEMENT_SET, ...SECONDARY_SET, ...FUNCTION_SET];
}
oop.inherits(MelfaHighlightRules, TextHighlightRules);

// ---- block structure for indenting ----
// A line is read without its leading step number and its comment.
const bare = (line) => line.replace(/^\s*\d+\s*/, "").replace(/'.*$/, "").trim().toUpperCase();
const opens = (text) =>
  (/^IF\b.*\bTHEN$/.test(text)) || // block IF: nothing after THEN
  /^FOR\b/.test(text) || /^WHILE\b/.test(text) || /^SELECT\b/.test(text) ||
  /^ELSE$/.test(text) || /^CASE\b/.test(text) || /^DEFAULT$/.test(text);
const CLOSER = /^(ENDIF|NEXT|WEND|ELSE|END\s+SELECT|CASE|DEFAULT)\b/;

/** The opener a closing line belongs to, as a test on bare lines (and what nests). */
function partnerOf(closer) {
  if (closer === "ENDIF" || closer === "ELSE") return { open: /^IF\b.*\bTHEN$/, close: /^ENDIF\b/ };
  if (closer === "NEXT") return { open: /^FOR\b/, close: /^NEXT\b/ };
  if (closer === "WEND") return { open: /^WHILE\b/, close: /^WEND\b/ };
  return { open: /^SELECT\b/, close: /^END\s+SELECT\b/ }; // END SELECT, CASE, DEFAULT
}

function MelfaMode() {
  this.HighlightRules = MelfaHighlightRules;
  this.$behaviour = this.$defaultBehaviour;
}
oop.inherits(MelfaMode, TextMode);

(function () {
  this.lineCommentStart = "'";
  this.$id = "ace/mode/melfa";

  this.getNextLineIndent = function (state, line, tab) {
    const indent = this.$getIndent(line);
    return opens(bare(line)) ? indent + tab : indent;
  };

  // Called before the typed text is inserted: outdent when it completes a closing word,
  // or when a label's `*` is typed at the start of an indented line.
  this.checkOutdent = function (state, line, input) {
    if (!/^[A-Za-z*]$/.test(input)) return false;
    const typed = (line + input).trim().toUpperCase();
    if (input === "*" && typed === "*" && /^\s+$/.test(line)) return true;
    return /^(ENDIF|NEXT|WEND|ELSE|END SELECT|CASE|DEFAULT)$/.test(typed);
  };

  this.autoOutdent = function (state, session, row) {
    const line = session.getLine(row);
    const text = bare(line);
    let target = "";
    if (!text.startsWith("*")) {
      const match = CLOSER.exec(text);
      if (!match) return;
      const closer = match[1].replace(/\s+/g, " ");
      const { open, close } = partnerOf(closer);
      let depth = 0;
      let found = null;
      for (let r = row - 1; r >= 0; r--) {
        const other = bare(session.getLine(r));
        if (close.test(other)) depth++;
        else if (open.test(other)) {
          if (depth === 0) { found = r; break; }
          depth--;
        }
      }
      if (found === null) return;
      target = this.$getIndent(session.getLine(found));
      // CASE / DEFAULT sit one step inside their SELECT.
      if (closer === "CASE" || closer === "DEFAULT") target += session.getTabString();
    }
    const current = this.$getIndent(line);
    if (current === target) return;
    const Range = ace.require("ace/range").Range;
    session.replace(new Range(row, 0, row, current.length), target);
  };
}).call(MelfaMode.prototype);

ace.define("ace/mode/melfa", ["require", "exports", "module"], (require, exports) => {
  exports.Mode = MelfaMode;
});

// A light theme in the page's palette (keywords blue, functions teal, labels purple…).
ace.define("ace/theme/melfa", ["require", "exports", "module", "ace/lib/dom"], (require, exports) => {
  exports.isDark = false;
  exports.cssClass = "ace-melfa";
  exports.cssText = `
.ace-melfa { background: #ffffff; color: #1d2733; }
.ace-melfa .ace_gutter { background: #f6f8fa; color: #8a96a3; border-right: 1px solid #e3e8ee; }
.ace-melfa .ace_gutter-active-line { background: #e9eef5; }
.ace-melfa .ace_marker-layer .ace_active-line { background: #f3f6fa; }
.ace-melfa .ace_marker-layer .ace_selection { background: #cfe0fb; }
.ace-melfa .ace_marker-layer .ace_selected-word { border: 1px solid #b5cdf5; }
.ace-melfa .ace_marker-layer .ace_bracket { margin: -1px 0 0 -1px; border: 1px solid #7aa2dc; background: #e6eefa; }
.ace-melfa .ace_cursor { color: #1f5fbf; }
.ace-melfa .ace_keyword { color: #1f4fa8; font-weight: 600; }
.ace-melfa .ace_keyword.ace_operator { color: #5f6b7a; font-weight: 400; }
.ace-melfa .ace_support.ace_function { color: #00796b; }
.ace-melfa .ace_constant.ace_language { color: #1f4fa8; font-weight: 600; }
.ace-melfa .ace_constant.ace_numeric { color: #b35900; }
.ace-melfa .ace_constant.ace_other.ace_linenumber { color: #9aa6b4; }
.ace-melfa .ace_string { color: #2e7d32; }
.ace-melfa .ace_comment { color: #7a8693; font-style: italic; }
.ace-melfa .ace_entity.ace_name.ace_label { color: #7b3fb3; font-weight: 600; }
.ace-melfa .ace_variable.ace_language { color: #a0266b; }
.ace-melfa .ace_variable.ace_parameter { color: #a0266b; }
.ace-melfa .ace_paren { color: #5f6b7a; }
.ace-melfa .ace_gutter-cell.ace_error { background-position: 2px center; }
`;
  require("ace/lib/dom").importCssString(exports.cssText, exports.cssClass, false);
});

export { MelfaMode };
