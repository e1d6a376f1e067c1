"""Hostile robot files (issue 24 item 1): deeply nested XML or TOML is a BadInput naming the
line, never a crash of the interpreter (15000 nested elements overflowed the URDF reader's stack,
SIGSEGV in Arm.from_file and Robot.from_toml)."""

import pytest

import freefloat as ff

DEPTH = 15000  # about 105 KB: within the 1 MiB limit of a robot file


def deep_urdf(depth):
    return '<robot name="r">\n<link name="base">\n' + "<a>" * depth + "</a>" * depth + "\n</link>\n</robot>\n"


@pytest.mark.parametrize("load", [ff.Arm.from_file, ff.Robot.from_toml])
def test_deeply_nested_urdf_is_bad_input(tmp_path, load):
    path = tmp_path / "deep.urdf"
    path.write_text(deep_urdf(DEPTH))
    with pytest.raises(ff.BadInput) as info:
        load(path)
    message = str(info.value)
    assert "nested deeper than 64 levels" in message and "line 3" in message, message
    assert len(message) < 500


@pytest.mark.parametrize(
    "value",
    ["[" * 100_000 + "]" * 100_000, "{a=" * 50_000 + "1" + "}" * 50_000],
    ids=["arrays", "inline-tables"],
)
@pytest.mark.parametrize("load", [ff.Arm.from_file, ff.Robot.from_toml])
def test_deeply_nested_toml_is_bad_input(tmp_path, load, value):
    path = tmp_path / "deep.toml"
    path.write_text("[robot]\nM = 12.9\nI = 0.208\nx = " + value + "\n")
    with pytest.raises(ff.BadInput) as info:
        load(path)
    assert len(str(info.value)) < 2000
