"""The pre-scan and MuJoCo agree on what ``<attach>`` attaches, or the file is refused.

MuJoCo names a ``<model>`` asset by its ``name``, else by its file's ``<mujoco model>``,
else ``MuJoCo Model``, and attaches the first asset of a name among those of the
document the ``<attach>`` stands in. The pre-scan counts what it resolves; a name two
assets share, a file MuJoCo would read as something else than MJCF, or names MuJoCo
would read in another encoding are refused before MuJoCo runs. Every case runs the
installed `cspace` command (``conftest.measured``), within the time and memory bounds.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from conftest import PEAK_MIB, SECONDS, assert_bounded_error, measured

pytestmark = pytest.mark.bounded
"""Every test here runs the command within the time and memory bounds."""

BOMB = (
    '<replicate count="60"><replicate count="60"><replicate count="60">'
    '<body><joint/><geom size=".1"/></body></replicate></replicate></replicate>'
)
"""216,000 bodies: MuJoCo took 476 MiB and 2.5-3.9 s to build it, then failed."""

ONE_BODY = '<worldbody><body name="one"><joint name="j"/><geom size=".1"/></body></worldbody>'


def _main(assets: str, attach: str) -> str:
    return (
        f'<mujoco model="r">\n<asset>\n{assets}\n</asset>\n'
        f'<worldbody><body name="t">{attach}</body></worldbody>\n</mujoco>\n'
    )


def _write(folder: Path, files: dict[str, str | bytes]) -> None:
    for name, text in files.items():
        (folder / name).parent.mkdir(parents=True, exist_ok=True)
        if isinstance(text, bytes):
            (folder / name).write_bytes(text)
        else:
            (folder / name).write_text(text)


def _report(folder: Path) -> dict[str, object]:
    result = measured("inspect", "--format", "json", "r.xml", cwd=folder)
    assert result.run.code == 0, result.run.stderr
    assert result.cpu_seconds < SECONDS and result.peak_mib < PEAK_MIB, result
    report: dict[str, object] = json.loads(result.run.stdout)
    return report


def _joint_names(report: dict[str, object]) -> list[str]:
    joints = report["joints"]
    assert isinstance(joints, list)
    return [str(joint["name"]) for joint in joints]


def test_an_unnamed_model_named_by_its_file_cannot_hide_behind_a_named_one(
    tmp_path: Path,
) -> None:
    # The measured case: the pre-scan counted b.xml (one body), MuJoCo attached a.xml,
    # the first model named "m" (216,000 bodies).
    _write(
        tmp_path,
        {
            "a.xml": f'<mujoco model="m"><worldbody>{BOMB}</worldbody></mujoco>',
            "b.xml": f"<mujoco>{ONE_BODY}</mujoco>",
            "r.xml": _main(
                '<model file="a.xml"/>\n<model name="m" file="b.xml"/>',
                '<attach model="m" prefix="p"/>',
            ),
        },
    )
    message = assert_bounded_error(measured("inspect", "r.xml", cwd=tmp_path), "bad-include")
    assert message.startswith("cspace: error: r.xml:4: ")
    assert '<model file="b.xml"> is named "m" (its name attribute)' in message
    assert '<model file="a.xml"> (line 3)' in message


@pytest.mark.parametrize(
    ("assets", "first", "second"),
    [
        # named first, then unnamed: whichever comes first, the name is ambiguous
        ('<model name="m" file="b.xml"/>\n<model file="a.xml"/>', "b.xml", "a.xml"),
        # neither names itself: both are "MuJoCo Model"
        ('<model file="c.xml"/>\n<model file="b.xml"/>', "c.xml", "b.xml"),
        # one name written with a line break, one with a reference to it: MuJoCo reads
        # both as "m\nx" (lxml reads the first as "m x")
        (
            '<model name="m\nx" file="a.xml"/>\n<model name="m&#10;x" file="b.xml"/>',
            "a.xml",
            "b.xml",
        ),
    ],
)
def test_two_models_of_one_name_are_refused(
    assets: str, first: str, second: str, tmp_path: Path
) -> None:
    _write(
        tmp_path,
        {
            "a.xml": f'<mujoco model="m"><worldbody>{BOMB}</worldbody></mujoco>',
            "b.xml": f"<mujoco>{ONE_BODY}</mujoco>",
            "c.xml": f"<mujoco>{ONE_BODY.replace('one', 'c')}</mujoco>",
            "r.xml": _main(assets, '<attach model="m" prefix="p"/>'),
        },
    )
    message = assert_bounded_error(measured("inspect", "r.xml", cwd=tmp_path), "bad-include")
    assert f'<model file="{second}"> is named' in message
    assert f'like <model file="{first}">' in message


def test_an_unattached_model_is_counted_too(tmp_path: Path) -> None:
    # MuJoCo parses every <model> asset, attached or not: this one alone took 1.2 GiB.
    _write(
        tmp_path,
        {
            "a.xml": f'<mujoco model="big"><worldbody>{BOMB}</worldbody></mujoco>',
            "r.xml": _main('<model file="a.xml"/>', ""),
        },
    )
    message = assert_bounded_error(measured("inspect", "r.xml", cwd=tmp_path), "too-many-joints")
    assert "(in a.xml, line 1)" in message


def test_an_unnamed_model_is_attached_and_counted_by_the_name_mujoco_gives_it(
    tmp_path: Path,
) -> None:
    files: dict[str, str | bytes] = {
        "kid.xml": f'<mujoco model="kid">{ONE_BODY}</mujoco>',
        "anon.xml": f"<mujoco>{ONE_BODY}</mujoco>",
        "r.xml": _main(
            '<model file="kid.xml"/>\n<model file="anon.xml"/>',
            '<attach model="kid" prefix="k"/><attach model="MuJoCo Model" prefix="a"/>',
        ),
    }
    _write(tmp_path, files)
    assert _joint_names(_report(tmp_path)) == ["t_fixed", "kj", "aj"]
    # counted, not only attached: 3 x 1,700 bodies is past the 5,001 cspace reads
    many = "".join(f'<body name="b{k}"><joint/><geom size=".1"/></body>' for k in range(1700))
    files["anon.xml"] = f"<mujoco><worldbody>{many}</worldbody></mujoco>"
    files["r.xml"] = _main(
        '<model file="anon.xml"/>',
        "".join(f'<attach model="MuJoCo Model" prefix="p{k}"/>' for k in range(3)),
    )
    _write(tmp_path, files)
    result = measured("inspect", "r.xml", cwd=tmp_path)
    assert "more than 5,001 bodies" in assert_bounded_error(result, "too-many-joints")


def test_an_attached_models_own_attach_names_its_own_assets(tmp_path: Path) -> None:
    # "m" is b.xml here and k.xml inside outer.xml: each <attach> looks among the assets
    # of its own document, as MuJoCo does.
    _write(
        tmp_path,
        {
            "b.xml": f"<mujoco>{ONE_BODY}</mujoco>",
            "k.xml": '<mujoco><worldbody><body name="kid"><joint name="kj"/><geom size=".1"/>'
            "</body></worldbody></mujoco>",
            "outer.xml": '<mujoco model="outer"><asset><model name="m" file="k.xml"/></asset>'
            '<worldbody><body name="o"><attach model="m" prefix="q"/></body></worldbody>'
            "</mujoco>",
            "r.xml": _main(
                '<model name="m" file="b.xml"/>\n<model file="outer.xml"/>',
                '<attach model="outer" prefix="p"/><attach model="m" prefix="s"/>',
            ),
        },
    )
    assert _joint_names(_report(tmp_path)) == ["t_fixed", "po_fixed", "pqkj", "sj"]


REFUSED = {
    "a URDF as a model": (
        {"r.urdf": '<robot name="rr"><link name="l"/></robot>'},
        '<model name="m" file="r.urdf"/>',
        "unsupported-element",
        "holds <robot>, not <mujoco>",
    ),
    "a model file MuJoCo hands to a decoder": (
        {"b.txt": f"<mujoco>{ONE_BODY}</mujoco>"},
        '<model name="m" file="b.txt"/>',
        "bad-include",
        "ends in .xml or .urdf",
    ),
    "an include spelt in capitals": (
        {"b.xml": f"<mujocoinclude>{ONE_BODY}</mujocoinclude>"},
        '</asset><INCLUDE file="b.xml"/><asset>',
        "bad-include",
        "<INCLUDE>: MuJoCo splices in an <include> whatever the case of its name",
    ),
    "names in Latin-1": (
        {
            "b.xml": b'<?xml version="1.0" encoding="ISO-8859-1"?>\n'
            + f'<mujoco model="caf\xe9">{ONE_BODY}</mujoco>'.encode("latin-1")
        },
        '<model file="b.xml"/>',
        "unsupported-encoding",
        "the file declares iso-8859-1, not UTF-8",
    ),
    "UTF-16 without a byte order mark": (
        {
            "b.xml": (
                '<?xml version="1.0" encoding="UTF-16"?>\n' + f"<mujoco>{ONE_BODY}</mujoco>"
            ).encode("utf-16-le")
        },
        '<model file="b.xml"/>',
        "unsupported-encoding",
        "the file is UTF-16 or UTF-32, not UTF-8",
    ),
}


@pytest.mark.parametrize("case", sorted(REFUSED))
def test_what_mujoco_would_read_otherwise_is_refused(case: str, tmp_path: Path) -> None:
    files, assets, code, said = REFUSED[case]
    _write(tmp_path, {**files, "r.xml": _main(assets, "")})
    assert said in assert_bounded_error(measured("inspect", "r.xml", cwd=tmp_path), code)
