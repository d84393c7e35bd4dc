"""iaa.eval against `iaa eval`: the same numbers, to the last bit, and the parser's messages."""

import re

import pytest

import iaa
from conftest import assert_same_error, cli_ok


def numbers(text):
    return [float(v) for v in re.findall(r"-?\d[\d.e+-]*|-?inf", text)]


def test_point_and_box_are_the_commands():
    expr = "x^2 + y^2 + z^2 - r^2 + sin(x*y)"
    out = cli_ok("eval", expr, "--param", "r=0.5", "--at", "0.3,-0.2,0.1",
                 "--box", "-0.1:0.2,0.3:0.4,-1:1")
    lines = {line.split("=")[0].strip(): line.split("=", 1)[1] for line in out.splitlines()
             if "=" in line}
    e = iaa.eval(expr, point=(0.3, -0.2, 0.1), box=((-0.1, 0.2), (0.3, 0.4), (-1, 1)),
                 params={"r": 0.5})
    assert [e.value] == numbers(lines["f"])
    assert list(e.gradient) == numbers(lines["grad f"])
    assert list(e.interval) == numbers(lines["F"])
    assert [v for i in e.interval_gradient for v in i] == numbers(lines["grad F"])
    assert e.partial_domain is False and e.certified_empty is False
    assert e.expression in out and e.operations > 0


def test_undefined_and_empty():
    e = iaa.eval("sqrt(x) - 1", point=(-1, 0, 0), box=(-2, -1, 0, 1, 0, 1))
    assert e.value is None and e.gradient is None
    assert e.interval is None and e.certified_empty
    e = iaa.eval("sqrt(x) - 1", box=(-1, 2, 0, 1, 0, 1))
    assert e.partial_domain and not e.certified_empty
    assert iaa.eval("x").interval is None  # nothing asked


def test_parse_errors_are_the_commands():
    for text in ("x^^2", "foo(x)", "x +"):
        assert_same_error(("eval", text, "--at", "0,0,0"),
                          lambda: iaa.eval(text, point=(0, 0, 0)))
    with pytest.raises(ValueError, match="box: every range"):
        iaa.eval("x", box=((1, 0), (0, 1), (0, 1)))
