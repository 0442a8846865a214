"""fnopt.Scene: the command line's settings, checks and error texts."""
import numpy as np
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
    assert repr(scene) == ("Scene(rows=10, cols=10, material='default', handles='corner', motion='rot_h0', "
                           "dt=0.016666666666666666, frames=3)")


def test_the_repr_shows_every_setting_off_its_default_and_evaluates_to_the_same_scene():
    scene = fnopt.Scene(res=12, stretch=80, gravity=(0, 0, -5), handles="none", placement="horizontal",
                        obstacles=["sphere center=0,0,-0.3 radius=0.2 friction=0.3"], contact_thickness=0.002)
    text = repr(scene)
    for shown in ("stretch=80", "gravity=(0, 0, -5)", "placement='horizontal'", "contact_thickness=0.002",
                  "obstacles=['sphere center=0,0,-0.3 radius=0.2 friction=0.3']"):
        assert shown in text
    assert eval(text, {"Scene": fnopt.Scene}) == scene


def test_every_scene_key_is_a_documented_keyword():
    keys = fnopt.scene_keys()
    assert [k.keyword for k in keys][:3] == ["res", "rows", "cols"]
    # An obstacle far away, so that the contact settings are written too.
    far = fnopt.Scene(obstacles=["plane point=0,0,-5 normal=0,0,1"])
    for key in keys:
        assert isinstance(key, fnopt.SceneKey)
        assert f"\n    {key.keyword} ({key.type}): " in fnopt.Scene.__doc__, key.keyword
        value = [key.example] if key.keyword == "obstacles" else key.example
        scene = far.replace(**{key.keyword: value})
        assert (scene.text != far.text) == (key.example != key.default), key.keyword


def test_obstacles_are_a_list_of_specs_and_the_cloth_stays_outside():
    scene = fnopt.Scene(res=10, frames=30, handles="none", placement="horizontal",
                        obstacles=["sphere center=0,0,-0.25 radius=0.2", "plane point=0,0,-0.5 normal=0,0,1"])
    assert len(scene.obstacles) == 2 and scene.obstacles[0].startswith("sphere")
    again = fnopt.Scene(res=10, frames=30, handles="none", placement="horizontal", obstacle=";".join(scene.obstacles))
    assert again == scene
    rollout = fnopt.run_rollout(scene, optimizer="pqn")
    positions = rollout.positions.reshape(-1, 3)
    assert np.isfinite(positions).all()
    # Outside the sphere and above the floor at every frame (the sphere is static).
    assert (np.linalg.norm(positions - np.array([0.0, 0.0, -0.25]), axis=1) >= 0.2).all()
    assert (positions[:, 2] >= -0.5).all()
    with pytest.raises(fnopt.Error, match="unknown shape 'cone'"):
        fnopt.Scene(res=10, obstacles=["cone center=0,0,-1 radius=1"])
