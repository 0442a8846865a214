"""fnopt.Scene: the command line's settings, checks and error texts."""
import pytest

import fnopt


def test_keywords_are_the_command_line_flags():
    scene = fnopt.Scene(res=12, handles="diagonal", motion="rot_h0", frames=7, gravity=(0, 0, -5), stretch=300.5)
    assert (scene.rows, scene.cols, scene.frames) == (12, 12, 7)
    assert scene.handles == "diagonal" and scene.motion == "rot_h0"
    assert scene.gravity == (0.0, 0.0, -5.0)
    assert scene.material.stretch == 300.5 and scene.handle_vertices == []
    # handle_vertices as pairs or as the flag's "i,j;i,j" text; read back as pairs
    explicit = fnopt.Scene(res=8, handle_vertices=[(0, 0), (0, 7)], motion="static")
    assert explicit.handle_vertices == [(0, 0), (0, 7)]
    assert fnopt.Scene(res=8, handle_vertices="0,0;0,7", motion="static") == explicit


def test_material_never_undoes_a_value_given_with_it():
    scene = fnopt.Scene(stretch=123.0, material="default")
    assert scene.material.stretch == 123.0


@pytest.mark.parametrize(
    "flags, keywords",
    [
        (["--res", "2"], {"res": 2}),
        (["--dt", "-1"], {"dt": -1}),
        (["--handles", "nowhere"], {"handles": "nowhere"}),
        (["--stretch", "nan"], {"stretch": float("nan")}),
        (["--handle-vertices", "0,0;99,99"], {"handle_vertices": "0,0;99,99"}),
    ],
)
def test_a_bad_scene_raises_value_error_with_the_command_lines_text(run_cli, tmp_path, flags, keywords):
    cli = run_cli("simulate", *flags, "--frames", "1", "--out", str(tmp_path / "r.h5"))
    assert cli.returncode != 0
    line = cli.stderr.strip().splitlines()[-1]
    with pytest.raises(ValueError) as raised:
        fnopt.Scene(**keywords)
    assert isinstance(raised.value, fnopt.Error)
    assert line == "fnopt: error: " + str(raised.value)


def test_scene_text_round_trips(tmp_path):
    scene = fnopt.Scene(res=10, motion="yz_v2", damping=2.5, frames=3)
    path = tmp_path / "scene.txt"
    path.write_text(scene.text)
    again = fnopt.Scene.load(str(path))
    assert again.text == scene.text
    assert fnopt.Scene(scene=str(path), frames=5).frames == 5
    assert scene.replace(frames=9).frames == 9 and scene.frames == 3


def test_material_is_a_read_only_record_equal_by_value():
    scene = fnopt.Scene(res=8, damping=2.5)
    material = scene.material
    assert isinstance(material, fnopt.Material)
    assert material == fnopt.Scene(res=8, damping=2.5).material
    assert material != fnopt.Scene(res=8).material
    assert material.damping == 2.5 and material.name == "default"
    with pytest.raises(AttributeError):
        material.damping = 1.0
    assert repr(material).startswith("Material(name='default', stretch=")


def test_scenes_are_equal_when_their_files_are_and_print_what_identifies_them():
    scene = fnopt.Scene(res=10, motion="rot_h0", frames=3)
    assert scene == fnopt.Scene(frames=3, motion="rot_h0", res=10)
    assert scene != scene.replace(frames=4) and scene != "a scene"
    text = repr(scene)
    assert text.startswith("Scene(rows=10, cols=10, handles='corner', motion='rot_h0', frames=3, dt=")
    assert float(text.rsplit("dt=", 1)[1].rstrip(")")) == pytest.approx(scene.dt, rel=1e-5)
