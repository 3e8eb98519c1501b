"""The written-out record classes (ngc2py.records) behave as the
dataclasses they replaced: constructor, ==, hash, repr and replace."""

from __future__ import annotations

import copy
import pickle

import pytest

from ngc2py import codegen, lexer, nodes, parser, records
from ngc2py import structure as st


def record_classes():
    """Every record class of the conversion path."""
    found = []
    for module in (nodes, st, parser, codegen, lexer):
        for value in vars(module).values():
            if (
                isinstance(value, type)
                and issubclass(value, records.Record)
                and value.__module__ == module.__name__
                and value._fields
            ):
                found.append(value)
    return found


def test_the_conversion_path_has_its_42_record_classes():
    assert len(record_classes()) == 42


@pytest.mark.parametrize("cls", record_classes(), ids=lambda cls: cls.__name__)
def test_a_record_is_made_from_its_fields_in_order(cls):
    # the constructor's parameters are the fields (the __slots__), in order
    code = cls.__init__.__code__
    parameters = code.co_varnames[1 : code.co_argcount]
    assert parameters == cls._fields
    assert cls.__match_args__ == cls._fields


def line(number=1, text="G0 X1"):
    return nodes.Line(number, text, "t.ngc")


def test_records_of_the_same_class_with_equal_fields_are_equal():
    word = nodes.Word("x", nodes.Num(1.0), 3)
    assert word == nodes.Word("x", nodes.Num(1.0), col=3)
    assert not word != nodes.Word("x", nodes.Num(1.0), col=3)
    assert word != nodes.Word("x", nodes.Num(1.0), col=4)
    assert st.Block(line()) == st.Block(line())
    assert st.Block(line()) != st.Block(line(2))


def test_records_of_different_classes_are_never_equal():
    assert nodes.NamedParam("a") != nodes.Exists("a")
    assert st.Block(line()) != st.Finish(line())
    loop = st.Loop("while", line())
    jump, do_end = st.Jump(line(), "continue", loop), st.DoEnd(line(), "continue", loop)
    assert jump != do_end and do_end != jump  # DoEnd extends Jump
    assert jump.__eq__(do_end) is NotImplemented
    assert nodes.Num(1.0) != 1.0
    assert nodes.Num(1.0).__eq__((1.0,)) is NotImplemented


def test_fields_compare_as_a_tuple():
    nan = float("nan")
    assert nodes.Num(nan) == nodes.Num(nan)  # the same object: equal in a tuple
    assert nodes.Num(float("nan")) != nodes.Num(float("nan"))


def test_nodes_hash_by_their_fields():
    assert hash(nodes.Num(2.0)) == hash((2.0,))
    word = nodes.Word("g", nodes.Num(1.0))
    assert hash(word) == hash(("g", nodes.Num(1.0), 0))
    assert len({nodes.Num(1.0), nodes.Num(1.0), nodes.Num(2.0)}) == 2


def test_values_are_unhashable_and_identity_records_hash_by_identity():
    for value in (
        st.Block(line()),
        st.Program("t.ngc", [], []),
        codegen.ItemRead("1.0", True),
        parser._Block(),
    ):
        with pytest.raises(TypeError):
            hash(value)
    sub, other = st.Sub(line(), "a"), st.Sub(line(), "a")
    assert sub != other and sub == sub  # eq=False: identity
    assert hash(sub) == object.__hash__(sub)
    assert len({st.Loop("while", line()), st.Loop("while", line())}) == 2


def test_frozen_records_hash_by_their_fields_and_cannot_be_changed():
    normalised = lexer.Normalised("g1x1", [0, 1, 3, 4])
    assert normalised == lexer.Normalised("g1x1", [0, 1, 3, 4])
    assert hash(lexer.Normalised("g1", (0, 1))) == hash(("g1", (0, 1), None))
    with pytest.raises(TypeError):
        hash(normalised)  # a list among its fields, as with a dataclass
    with pytest.raises(AttributeError, match="cannot assign to field 'text'"):
        normalised.text = "x"
    with pytest.raises(records.FrozenError):
        del normalised.error
    parsed = parser.ParsedFile("t.ngc", [], False, False)
    with pytest.raises(AttributeError):
        parsed.closed = True
    assert parsed.closed is False


def test_frozen_records_copy_and_pickle():
    normalised = lexer.Normalised("g1", [0, 1], "Unclosed comment found")
    assert copy.copy(normalised) == normalised
    assert copy.deepcopy(normalised) == normalised
    assert pickle.loads(pickle.dumps(normalised)) == normalised


def test_repr_is_a_dataclass_s():
    assert (
        repr(nodes.Word("x", nodes.Num(1.0)))
        == "Word(letter='x', value=Num(value=1.0), col=0)"
    )
    assert repr(st.Finish(nodes.Line(1, "%"))).startswith(
        "Finish(line=Line(number=1, text='%', file=''"
    )
    # a hidden field is not shown
    opened = st._Open("1", None, [], condition=("x",))
    assert repr(opened) == "_Open(label='1', node=None, body=[])"
    assert opened == st._Open("1", None, [])  # nor compared


def test_a_record_met_again_inside_its_own_repr_shows_as_dots():
    loop = st.Loop("while", nodes.Line(1, "o1 while [1]"))
    loop.body.append(st.Jump(nodes.Line(2, "o1 break"), "break", loop))
    text = repr(loop)
    assert "Jump(line=Line(number=2, text='o1 break'" in text
    assert "target=..., flag='')" in text
    assert text.startswith("Loop(kind='while', ") and text.endswith("anew=None)")


def test_replace_makes_a_new_record_with_changes():
    old = nodes.Line(3, "G1 X1", "t.ngc", n=10.0)
    new = records.replace(old, error="Bad", n_text="10")
    assert new is not old and type(new) is nodes.Line
    assert (new.number, new.text, new.file, new.n) == (3, "G1 X1", "t.ngc", 10.0)
    assert (new.error, new.n_text, old.error, old.n_text) == ("Bad", "10", None, None)
    assert records.replace(old) == old
    parsed = parser.ParsedFile("t.ngc", [old], True, False)
    assert records.replace(parsed, closed=True) == parser.ParsedFile(
        "t.ngc", [old], True, True
    )
    with pytest.raises(TypeError):
        records.replace(old, colour="red")


def test_default_factories_give_each_record_its_own():
    a, b = st.Loop("while", line()), st.Loop("while", line())
    assert a.body == [] and a.body is not b.body and a.exits is not b.exits
    a, b = st.Program("t.ngc", [], []), st.Program("t.ngc", [], [])
    assert (a.externals, a.found) == ([], {})
    assert a.externals is not b.externals and a.found is not b.found
    a, b = parser._Block(), parser._Block()
    assert a.groups == {"g": {}, "m": {}} and a.groups is not b.groups
    assert a.groups["g"] is not b.groups["g"] and a.items is not b.items
    assert (
        codegen.ItemRead("x", False).checks is not codegen.ItemRead("x", False).checks
    )
    assert st.Sub(line(), "a").body is not st.Sub(line(), "a").body
    assert st.If([]).landings is not st.If([]).landings
    given = []
    assert st.Branch(line(), given).body is given


def test_constructors_take_fields_by_position_and_by_name():
    assert nodes.OWord("call", "1", (nodes.Num(2.0),)) == nodes.OWord(
        keyword="call", name="1", args=(nodes.Num(2.0),)
    )
    with pytest.raises(TypeError):
        nodes.Num()
    with pytest.raises(TypeError):
        nodes.Word("x", nodes.Num(1.0), 0, 1)


def test_subexpressions_walks_the_fields():
    expr = nodes.Binary(
        "+", nodes.NumParam(nodes.Num(1.0)), nodes.Unary("neg", nodes.NamedParam("a"))
    )
    walked = [type(e).__name__ for e in nodes.subexpressions(expr)]
    assert walked == ["Binary", "NumParam", "Num", "Unary", "NamedParam"]
