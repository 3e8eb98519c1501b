"""Files whose O-words do not nest, compiled line by line.

rs274 does not pair O-words: it skips forward to the next line with a label,
landing wherever that is, and seeks back to where a label was recorded.
Where a file's O-words nest as Python blocks do (each construct closed by
its own lines, in order, each label used by one construct of its scope),
that is exactly what the nested Python of ``structure.py`` and
``codegen.py`` does. Where they do not (a skip landing inside a construct
it never opened, a label reused by constructs of other kinds, an arm line
outside its if), what runs depends on rs274's state in ways the nested
form can only approximate. Such a file is written instead as one function,
``main()``, that runs the file's lines in the order
``runtime.oflow.Flow`` gives them, following rs274's own rules: a branch
per line, with the line's code (or, for an O-word line, what its reading
evaluates), and a table ``LINES`` of what each line's O-word is.

Files with an ``M99``, an ``M98 .. L``, both ``M98`` and a Fanuc-style
subroutine (``O100``), or computed labels keep the nested form: their
frames and searches are the runtime's (runtime/fanuc_subs.py), which the
line-by-line form does not follow. An ``M98`` calling another file's
subroutine is followed (rs274 reads its words even skipping over the
line), and so is an ``O100`` line no ``M98`` can run (it does nothing).
"""

from __future__ import annotations


from ngc2py import codegen
from ngc2py import structure as st
from ngc2py.codegen import INDENT, ModuleWriter, identifier, string
from ngc2py.rowrun import RowRun

# typing is for the checker only: importing it costs a conversion 5 ms
TYPE_CHECKING = False
if TYPE_CHECKING:
    from typing import Dict, List, Optional

_OPENERS = ("if", "do", "while", "repeat")


def _file_lines(lines: list, demarcated: bool) -> Optional[list]:
    """The lines rs274 can read (to the closing ``%``, that line included);
    None where the line-by-line form cannot follow the file."""
    out = []
    opened = not demarcated
    for line in lines:
        if type(line) is RowRun:
            out.append(line)  # data rows: ordinary lines, kept as one run
            continue
        if line.percent and line.error is None:
            if not opened:
                opened = True
                continue
            out.append(line)
            break
        if getattr(line, "fanuc_alt", None) is not None:
            return None  # "M#1 P100": an M98 when #1 is 98
        word = line.oword
        if word is not None:
            if word.keyword == "m99" or not isinstance(word.name, str):
                return None
            if word.keyword == "m98" and word.expr is not None:
                return None  # M98 .. L: an L0 frame names labels its own way
        out.append(line)
    keywords = {line.oword.keyword for line in out if line.oword is not None}
    if "fanuc_sub" in keywords and "m98" in keywords:
        return None  # an M98 may run this file's Fanuc subroutine
    return out


def nests(lines: list) -> bool:
    """Do the O-words of ``lines`` nest as Python blocks do?

    Each construct is closed by its own lines in order (an if's elseif and
    else lines before its endif, none after its else; a do closed by its
    while line), each label is used by one construct of its scope (a
    subroutine's, or the main program's), a break or continue names a
    while or do loop around it, definitions stand outside every construct,
    and ``return`` only inside one. Lines that are block-deleted do
    something different with and without ``-b``: an O-word on such a line
    does not nest."""
    stack: List[list] = []  # [keyword, key, else seen]
    used: set = set()
    sub: Optional[str] = None
    for line in lines:
        word = line.oword
        if word is None or line.percent:
            continue
        if line.block_delete or line.oword_unread:
            return False
        keyword, name = word.keyword, word.name
        key = "%s#%s" % (sub or "", name)
        top = stack[-1] if stack else None
        if keyword == "sub":
            if sub is not None or stack or name in used:
                return False
            sub = name
            used.add(name)
        elif keyword == "endsub":
            if sub != name or stack:
                return False
            sub = None
        elif keyword == "return":
            if sub != name:
                return False
        elif keyword in ("call", "fanuc_sub"):
            continue  # (a Fanuc O-line no M98 calls does nothing)
        elif keyword == "m98":
            # rs274 reads an M98 line in full even skipping over it: a value
            # that can fail fails wherever the line is, which only the line
            # by line form follows
            if any(codegen.may_fail(item.value) for item in line.items):
                return False
        elif keyword in _OPENERS:
            if keyword == "while" and top is not None and top[:2] == ["do", key]:
                stack.pop()  # the end of a do-loop
                continue
            if key in used:
                return False
            used.add(key)
            stack.append([keyword, key, False])
        elif keyword in ("elseif", "else"):
            if top is None or top[:2] != ["if", key] or top[2]:
                return False
            top[2] = keyword == "else"
        elif keyword == "endif":
            if top is None or top[:2] != ["if", key]:
                return False
            stack.pop()
        elif keyword in ("endwhile", "endrepeat"):
            if top is None or top[:2] != [keyword[3:], key]:
                return False
            stack.pop()
        elif keyword in ("break", "continue"):
            if not any(entry[:2] in (["while", key], ["do", key]) for entry in stack):
                return False
        else:
            return False
    return not stack and sub is None


def flat_program(
    program: st.Program, lines: list, demarcated: bool
) -> Optional[st.Program]:
    """``program`` as the line-by-line form sees it, or None where its
    O-words nest (or it is a Fanuc-style file: see the module's doc).

    Its body is one statement per line (calls as :class:`structure.Call`,
    so the compiler finds and resolves them as usual), its subroutines one
    per ``sub`` line (what a call of the name runs)."""
    if program.open_error is not None:
        return None
    read = _file_lines(lines, demarcated)
    if read is None or nests(read):
        return None
    body: List[st.Stmt] = []
    subs: List[st.Sub] = []
    for line in read:
        word = line.oword
        if line.percent:
            body.append(st.Finish(line))
        elif word is None or line.error is not None:
            body.append(st.Block(line))
        elif word.keyword == "call":
            body.append(st.Call(line, word.name, word.args))
        elif word.keyword == "m98":
            body.append(st.FanucCall(line))
        else:
            body.append(st.Block(line))
        if (
            word is not None
            and word.keyword == "sub"
            and line.error in (None, st.AFTER_OWORD)
        ):
            subs.append(st.Sub(line, word.name))
    flat = st.Program(program.file, body, subs, last=program.last)
    flat.lines = read  # (read by FlowGen)
    return flat


class FlowGen(codegen.CodeGen):
    """Writes a :func:`flat_program` as ``lines()`` (see the module's doc)."""

    def __init__(self, program, source_name, opening=None, pack=True):
        super().__init__(program, source_name, opening, pack)
        self.settled = {}  # any line may be skipped: nothing is certainly set
        self.entries: Dict[int, st.Sub] = {}
        self.entry_items: Dict[int, List[str]] = {}

    def module(self) -> str:
        subs = list(self.program.subs) + list(self.program.externals)
        for sub in subs:
            sub.fn = identifier(sub.name, "o_", self.names)
        self.entries = {sub.line.number: sub for sub in self.program.subs}
        body = ModuleWriter(self.files)
        self.w = body
        if self.opening is not None:
            body.texts[0][self.opening.number] = self.opening.text
        for sub in self.program.externals:
            self.function(sub)
        for sub in self.program.subs:
            self.entry(sub)
        table = self.lines_function()
        self.w.raw("")
        self.w.raw("")
        self.w.raw("#: What each line that does something is, for runtime.oflow.Flow:")
        self.w.raw(
            '#: "" an ordinary line ("/" block-deleted, "x" or "u" unreadable), the'
        )
        self.w.raw(
            "#: line after a run of ordinary lines, or an O-word (keyword, label,"
        )
        self.w.raw("#: flags); the end of the file last.")
        one_line = "LINES = {%s}" % ", ".join(table)
        if len(one_line) <= codegen.LINE_LENGTH:
            self.w.raw(one_line)
        else:  # black puts a dict that does not fit one entry a line
            self.w.raw("LINES = {")
            for entry in table:
                text = "%s%s," % (INDENT, entry)
                if len(text) > codegen.LINE_LENGTH and entry.endswith(")"):
                    # (a long label) and an entry that does not fit one item a line
                    key, items = entry[:-1].split(": (", 1)
                    self.w.raw("%s%s: (" % (INDENT, key))
                    for item in self.entry_items[int(key)]:
                        self.w.raw("%s%s," % (INDENT * 2, item))
                    self.w.raw("%s)," % INDENT)
                    continue
                self.w.raw(text)
            self.w.raw("}")
        return self.assemble(body)

    def end_of_main(self):
        closing = [s for s in self.program.body if isinstance(s, st.Finish)]
        if closing:
            return closing[0].line.number, True
        last = self.program.last
        return (last.number if last is not None else 0), False

    def entry(self, sub: st.Sub) -> None:
        """What a call of ``sub`` runs: the file's lines from its sub line."""
        ends = [
            line.number
            for line in self.program.lines
            if line.oword is not None
            and line.oword.keyword == "endsub"
            and line.oword.name == sub.name
            and line.number > sub.line.number
        ]
        end = ends[0] if ends else sub.line.number
        self.w.raw("")
        self.w.raw("")
        for text in codegen.def_header(sub.fn):
            self.w.raw(text)
        doc = "o<%s> sub (lines %d-%d), run line by line: see main()" % (
            codegen.safe_doc(sub.name),
            sub.line.number,
            end,
        )
        self.w.raw('%s"""%s"""' % (INDENT, doc))
        self.w.depth = 1
        self.w.stmt(
            "return main(m, %d, %s)" % (sub.line.number, string(sub.name)), sub.line
        )
        self.w.depth = 0

    def lines_function(self) -> List[str]:
        """Write ``main()``, the file line by line; return the entries of
        the ``LINES`` table."""
        w = self.w
        w.raw("")
        w.raw("")
        w.raw("def main(m: Machine, at: int = 1, sub=None):")
        w.raw(
            '%s"""The main program, and a call of subroutine ``sub`` from its sub\n'
            "%sline ``at``: the file one line at a time. Its O-words do not nest,\n"
            '%sso rs274\'s rules decide which line comes next (runtime.oflow)."""'
            % (INDENT, INDENT, INDENT)
        )
        w.depth = 1
        stores = self.stores()
        w.raw(INDENT + "f = m.flow(LINES, at, sub)")
        w.raw(INDENT + "while True:")
        w.depth = 2
        # errors of the O-words read here name their line themselves
        w.row_loop("at = f.next()")
        w.depth = 1
        w.raw(INDENT * 2 + "if at == 0:")
        w.raw(INDENT * 3 + "return f.value")
        table: List[str] = []
        by_number = {}
        for stmt in self.program.body:
            by_number[stmt.line.number] = stmt
        for part in self.parts():
            line = part[0]
            if len(part) > 1 or type(line) is RowRun and line.count > 1:
                # ordinary lines one after another: no skip lands among them
                # and none starts there, so they run (or are passed) together
                last = part[-1]
                after = last.number + (last.count if type(last) is RowRun else 1)
                table.append("%d: %d" % (line.number, after))
                w.raw(INDENT * 2 + "if at == %d:" % line.number)
                w.depth = 3
                self.block([by_number[one.number] for one in part])
                w.raw(INDENT * 3 + "continue")
                continue
            stmt = by_number[line.number]
            entry = self.entry_of(line)
            if entry is None:
                continue
            table.append("%d: %s" % (line.number, entry))
            if line.oword is not None or line.error is not None:
                w.texts[0][line.number] = line.text  # for rs274's messages
            code = self.code_for(stmt, line)
            if code is None:
                continue
            w.raw(INDENT * 2 + "if at == %d:" % line.number)
            w.depth = 3
            code()
            w.raw(INDENT * 3 + "continue")
        last = self.program.last
        if not any(isinstance(s, st.Finish) for s in self.program.body):
            end = (last.number if last is not None else 0) + 1
            table.append('%d: "%s"' % (end, "eof%" if self.demarcated else "eof"))
        w.depth = 1
        self.bind_stores(stores)
        w.depth = 0
        return table

    def parts(self) -> List[list]:
        """The file's lines, runs of plain ordinary lines (no O-word, no
        error, no block delete: what rs274 runs alike, or passes alike
        while skipping) together, every other line alone."""
        parts: List[list] = []
        run: list = []
        for line in self.program.lines:
            plain = (
                line.oword is None
                and line.error is None
                and not line.block_delete
                and not line.percent
            )
            if plain and not getattr(line, "is_blank", False):
                run.append(line)
                continue
            if plain:
                continue  # a blank line inside a run leaves it one run
            if run:
                parts.append(run)
                run = []
            parts.append([line])
        if run:
            parts.append(run)
        return parts

    def entry_of(self, line) -> Optional[str]:
        """``line``'s entry in ``LINES`` (None: a blank line)."""
        if line.percent:
            return '"%"'
        word = line.oword
        if line.error in st.TEXT_ERRORS:
            if word is None:
                return '"x"'
            return self.o_entry(
                line, [string(word.keyword), string(str(word.name)), '"x"']
            )
        if word is None and line.oword_unread:
            # an O-word rs274 cannot read: it fails even skipping past it
            flags = "u" + ("k" if line.error == st.UNKNOWN_O_COMMAND else "")
            return string(flags + ("/" if line.block_delete else ""))
        if word is None:
            if getattr(line, "is_blank", False):
                return None
            return '"/"' if line.block_delete else '""'
        flags = ""
        if word.keyword in ("if", "elseif", "while", "repeat", "call", "sub", "m98"):
            flags += "v"
        elif word.keyword in ("return", "endsub") and (
            word.expr is not None or line.error not in (None, st.AFTER_OWORD)
        ):
            flags += "v"
        elif line.error not in (None, st.AFTER_OWORD):
            flags += "v"
        if line.error == st.AFTER_OWORD:
            flags += "t"
        if line.block_delete:
            flags += "/"
        if line.oword_unread:
            flags += "u"
            if line.error == st.UNKNOWN_O_COMMAND:
                flags += "k"
        items = [string(word.keyword), string(str(word.name)), string(flags)]
        return self.o_entry(line, items)

    def o_entry(self, line, items: List[str]) -> str:
        """An O-word line's entry, its items kept for a long one's layout."""
        self.entry_items[line.number] = items
        return "(%s)" % ", ".join(items)

    def code_for(self, stmt, line):
        """A writer of the code the module runs for ``line`` (None: none)."""
        word = line.oword
        if line.percent:
            return None
        if word is None and line.error in st.TEXT_ERRORS:
            return lambda: self.read_error(line)  # -b or not
        if word is None:
            return lambda: self.block([stmt])
        if line.error is not None and line.error != st.AFTER_OWORD:
            return lambda: self.read_error_both(line)
        keyword = word.keyword
        if keyword == "sub":
            sub = self.entries.get(line.number)
            if sub is None:
                return None
            return lambda: self.w.stmt("f.define(%s)" % sub.fn, line)
        if keyword == "call":
            return lambda: self.s_call(stmt)
        if keyword == "m98":
            return lambda: self.m98(stmt)
        if keyword in ("if", "elseif", "while", "repeat"):
            return lambda: self.w.stmt("f.o(%s)" % self.x.expr(word.expr), line)
        if keyword in ("return", "endsub") and word.expr is not None:
            return lambda: self.value_both(line, word.expr)
        return None

    def m98(self, stmt: st.FanucCall) -> None:
        """An M98 line: rs274 reads its words also when it skips over the
        line (their values evaluated, a named parameter not set reading 0
        in a definition), and calls only when it runs it."""
        line = stmt.line
        self.w.stmt("if f.runs():", line)
        self.w.depth += 1
        self.s_fanuccall(stmt)
        self.w.depth -= 1
        plain = self.m98_reads_of(line)
        if not plain:
            return
        defining = self.m98_reads_of(line, defining=True)
        if defining != plain:
            self.w.stmt("elif f.defining:", line)
            self.w.depth += 1
            for code in defining:
                self.w.stmt(code, line)
            self.w.depth -= 1
        self.w.stmt("else:  # rs274 reads the line while skipping it", line)
        self.w.depth += 1
        for code in plain:
            self.w.stmt(code, line)
        self.w.depth -= 1

    def value_both(self, line, expr) -> None:
        """A return or endsub value: read past a definition, a named
        parameter not set reads 0 (codegen.definition_value)."""
        value = self.x.expr(expr)
        self.x.defining = True
        try:
            defining = self.x.expr(expr)
        finally:
            self.x.defining = False
        if defining == value:
            self.w.stmt("f.o(%s)" % value, line)
            return
        self.w.stmt("f.o(%s if f.defining else %s)" % (defining, value), line)

    def read_error_both(self, line) -> None:
        """A line rs274 fails to read: what it computed before the error,
        then the failure (a return or endsub value as read past a
        definition, where that differs)."""
        word = line.oword
        if word is not None and word.keyword in ("return", "endsub"):
            self.w.stmt("if f.defining:", line)
            self.w.depth += 1
            self.x.defining = True
            try:
                self.read_error(line)
            finally:
                self.x.defining = False
            self.w.depth -= 1
        self.read_error(line)


def generate(
    program: st.Program, source_name: str, opening=None, pack: bool = True
) -> str:
    """The module text of a :func:`flat_program` (``pack``: see
    codegen.source_map_lines)."""
    return FlowGen(program, source_name, opening, pack).module()
