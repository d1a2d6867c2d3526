"""What urdfdom reads and XML forbids, read as urdfdom reads it (pybullet's files do it).

White space before the XML declaration, and NUL bytes after the root element: each an
``xml-lenient`` finding, the report the same as the clean file's (Pinocchio's own parser
is the oracle), line numbers kept. Anything else after the root element is refused with
a message that says so, not "truncated".
"""

from __future__ import annotations

from pathlib import Path

import pinocchio

import cspace

from conftest import run_cli

ARM = (
    '<robot name="arm">\n<link name="a"/>\n<link name="b"/>\n'
    '<joint name="j" type="revolute">\n<parent link="a"/><child link="b"/>\n'
    '<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/>\n'
    "</joint>\n</robot>\n"
)


def _lenient(tmp_path: Path, data: bytes) -> cspace.Report:
    path = tmp_path / "arm.urdf"
    path.write_bytes(data)
    report = cspace.inspect(path)
    clean = pinocchio.buildModelFromXML(ARM)  # what urdfdom reads, through Pinocchio
    assert (report.nq, report.nv) == (clean.nq, clean.nv)
    assert report.manifold.notation == "R^1"
    return report


def test_white_space_before_the_declaration(tmp_path: Path) -> None:
    report = _lenient(tmp_path, b'\n\n<?xml version="1.0" encoding="utf-8"?>\n' + ARM.encode())
    (said,) = [d for d in report.diagnostics if d.code == "xml-lenient"]
    assert "before the XML declaration" in said.message
    assert report.joints[0].line == 7  # the joint's own line, counted from the file's start


def test_nul_bytes_after_the_root_element(tmp_path: Path) -> None:
    report = _lenient(tmp_path, ARM.encode() + b"\r\n\x00\x00")
    (said,) = [d for d in report.diagnostics if d.code == "xml-lenient"]
    assert "NUL" in said.message


def test_a_clean_file_has_no_such_finding(tmp_path: Path) -> None:
    report = _lenient(tmp_path, ARM.encode())
    assert not [d for d in report.diagnostics if d.code == "xml-lenient"]


def test_a_late_declaration_of_another_encoding_is_still_refused(tmp_path: Path) -> None:
    path = tmp_path / "arm.urdf"
    path.write_bytes(b'\n<?xml version="1.0" encoding="ISO-8859-1"?>\n' + ARM.encode())
    run = run_cli("inspect", str(path))
    assert run.code == 2 and "[xml-syntax]" in run.stderr


def test_content_after_the_root_element_is_named_for_what_it_is(tmp_path: Path) -> None:
    for tail in (b"<robot/>", b"stray", b"\x00stray"):
        path = tmp_path / "arm.urdf"
        path.write_bytes(ARM.encode() + tail)
        run = run_cli("inspect", str(path))
        assert run.code == 2 and "[xml-syntax]" in run.stderr, tail
        assert "truncated" not in run.stderr, (tail, run.stderr)


def test_urdf_1_1_quat_xyzw_as_urdfdom_reads_it(tmp_path: Path) -> None:
    def with_origin(origin: str) -> Path:
        path = tmp_path / "arm.urdf"
        path.write_text(ARM.replace("<parent link=", f"{origin}<parent link="))
        return path

    alone = cspace.inspect(with_origin('<origin xyz="0 0 1" quat_xyzw="0 0 0 1"/>'))
    assert alone.manifold.notation == "R^1"
    both = run_cli("inspect", str(with_origin('<origin rpy="0 0 0" quat_xyzw="0 0 0 1"/>')))
    assert both.code == 2 and "[conflicting-attributes]" in both.stderr
    assert "arm.urdf:5:" in both.stderr and "'rpy' and 'quat_xyzw'" in both.stderr
    bad = run_cli("inspect", str(with_origin('<origin quat_xyzw="0 0 1"/>')))
    assert bad.code == 2 and "[bad-number]" in bad.stderr


def test_a_late_declaration_after_a_byte_order_mark_or_of_ascii(tmp_path: Path) -> None:
    _lenient(tmp_path, b'\xef\xbb\xbf\n<?xml version="1.0"?>\n' + ARM.encode())
    _lenient(tmp_path, b'\n<?xml version="1.0" encoding="ascii"?>\n' + ARM.encode())
