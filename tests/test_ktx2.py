"""KTX2 textures as a web volumetric player ships them (tvmedit.engine.capture.ktx2).

A player's layout is made from twelve frames of the real scvv capture: their Draco meshes in
``geometry_draco/``, their JPG textures flipped (as the uvol encoder's ``basisu -y_flip``
stores them) and packed five frames to a Basis Universal (UASTC) KTX2 file in
``texture_ktx2-fps30-1k_baseColor_default/``. alktx2 writes one layer a file; the arrays are
put together here from its files, as ``basisu -tex_type video`` writes them.
"""

import shutil
import struct
import sys

import numpy as np
import pytest

from tvmedit.cli import main
from tvmedit.engine.errors import InputError, TvmError
from tvmedit.engine.capture.ktx2 import IDENTIFIER, KtxLayer, layer_count
from tvmedit.engine.capture.load import open_sequence
from tvmedit.engine.capture.readers import read_image, read_mesh, texture_for

from test_readers import CARD

alktx2 = pytest.importorskip("alktx2", reason="KTX2 textures need the alktx2 package (tvmedit[ktx2])")
pytestmark = pytest.mark.skipif(not CARD.is_dir(), reason=f"the scvv capture is not at {CARD}")

FRAMES, BATCH = 12, 5


def ktx2_array(images):
    """One UASTC KTX2 file whose layers are ``images`` ((H, W, 3) uint8, row 0 stored first)."""
    singles = [alktx2.encode_raw_rgba_to_ktx2(np.dstack([image, np.full(image.shape[:2], 255, np.uint8)]).tobytes(),
                                              image.shape[1], image.shape[0], has_alpha=False, codec="uastc")
               for image in images]

    def parts(data):
        head = list(struct.unpack("<9I", data[12:48]))
        dfd_at, dfd_size, kvd_at, kvd_size = struct.unpack("<4I", data[48:64])
        level_at, level_size, _ = struct.unpack("<3Q", data[80:104])
        return head, data[dfd_at:dfd_at + dfd_size], data[kvd_at:kvd_at + kvd_size], data[level_at:level_at + level_size]

    head, dfd, kvd, _ = parts(singles[0])
    assert head[7] == 1 and head[8] == 0    # one level, no supercompression: layers simply follow
    levels = b"".join(parts(data)[3] for data in singles)
    head[5] = len(images)
    dfd_at, kvd_at = 104, 104 + len(dfd)
    level_at = kvd_at + len(kvd) + (-(kvd_at + len(kvd)) % 16)
    out = (IDENTIFIER + struct.pack("<9I", *head) + struct.pack("<4I", dfd_at, len(dfd), kvd_at, len(kvd))
           + struct.pack("<2Q", 0, 0) + struct.pack("<3Q", level_at, len(levels), len(levels)) + dfd + kvd)
    return out + b"\0" * (level_at - len(out)) + levels


@pytest.fixture(scope="module")
def player_take(tmp_path_factory):
    """The card's first twelve frames as a player's export, and their JPG textures."""
    from PIL import Image

    top = tmp_path_factory.mktemp("uvol") / "card-web"
    geometry, textures = top / "geometry_draco", top / "texture_ktx2-fps30-1k_baseColor_default"
    geometry.mkdir(parents=True)
    textures.mkdir()
    meshes = sorted(CARD.glob("*.draco"))[:FRAMES]
    images = []
    for index, mesh in enumerate(meshes):
        shutil.copy(mesh, geometry / f"{index:05d}.drc")
        images.append(np.asarray(Image.open(mesh.with_suffix(".jpg")).convert("RGB")))
    for first in range(0, FRAMES, BATCH):
        batch = [image[::-1] for image in images[first:first + BATCH]]   # basisu -y_flip
        (textures / f"texture_{first // BATCH:07d}.ktx2").write_bytes(ktx2_array(batch))
    (top / "audio.mp3").write_bytes(b"ID3")
    return top, images


def test_each_frame_shows_its_layer_the_right_way_up(player_take):
    top, images = player_take
    assert [layer_count(p) for p in sorted((top / "texture_ktx2-fps30-1k_baseColor_default").glob("*.ktx2"))] == [5, 5, 2]
    for index in (0, 4, 5, 11):
        mesh = read_mesh(top / "geometry_draco" / f"{index:05d}.drc")
        assert mesh.texture_path == KtxLayer(mesh.texture_path.path, index % BATCH)
        assert mesh.texture_path.path.name == f"texture_{index // BATCH:07d}.ktx2"
        # UASTC keeps the picture within a few grey levels; upside down it would be far off.
        assert np.abs(mesh.texture.astype(int) - images[index]).mean() < 6
        assert np.abs(mesh.texture[::-1].astype(int) - images[index]).mean() > 20


def test_the_player_export_checks_from_its_top_folder_textured_at_its_stated_rate(player_take, capsys):
    top, _ = player_take
    assert main(["check", str(top)]) == 0
    out = capsys.readouterr().out
    assert f"textures: {FRAMES} of {FRAMES} frames (512x256)" in out
    assert open_sequence(top).fps == 30.0


def test_a_frame_past_the_last_layer_has_no_texture(player_take, tmp_path):
    top, _ = player_take
    longer = tmp_path / "longer"
    shutil.copytree(top, longer)
    shutil.copy(longer / "geometry_draco" / "00011.drc", longer / "geometry_draco" / "00012.drc")
    assert texture_for(longer / "geometry_draco" / "00012.drc") is None
    assert read_mesh(longer / "geometry_draco" / "00012.drc").texture is None


def test_without_the_decoder_a_ktx2_texture_is_one_sentence(player_take, monkeypatch):
    top, _ = player_take
    monkeypatch.setitem(sys.modules, "alktx2", None)
    layer = texture_for(top / "geometry_draco" / "00000.drc")
    with pytest.raises(TvmError, match=r"is a KTX2 \(Basis Universal\) texture, which needs the alktx2 package; "
                                         r"install it with: pip install 'tvmedit\[ktx2\]'\.$"):
        read_image(layer)


def test_frames_mixing_drc_and_draco_count_as_one_sequence_and_read_geometry_without_textures(player_take, tmp_path):
    top, images = player_take
    mixed = tmp_path / "mixed"
    shutil.copytree(top, mixed)
    (mixed / "geometry_draco" / "00003.drc").rename(mixed / "geometry_draco" / "00003.draco")
    mesh = read_mesh(mixed / "geometry_draco" / "00004.drc")
    assert mesh.texture_path.layer == 4 and np.abs(mesh.texture.astype(int) - images[4]).mean() < 6
    # Reading geometry alone never opens a texture: a broken one does not stop the features.
    (mixed / "texture_ktx2-fps30-1k_baseColor_default" / "texture_0000000.ktx2").write_bytes(b"broken")
    assert len(read_mesh(mixed / "geometry_draco" / "00004.drc", "geometry").vertices)


def test_a_file_named_ktx2_that_is_not_is_named(tmp_path):
    bad = tmp_path / "t.ktx2"
    bad.write_bytes(b"not a texture at all, just text" * 3)
    with pytest.raises(InputError, match="is not a KTX2 file"):
        layer_count(bad)
    with pytest.raises(InputError, match="cannot be decoded as Basis Universal KTX2"):
        read_image(KtxLayer(bad, 0))


def test_a_texture_left_as_a_git_lfs_pointer_is_named_in_one_sentence(player_take, tmp_path, capsys):
    top, _ = player_take
    cloned = tmp_path / "cloned"
    shutil.copytree(top, cloned)
    first = cloned / "texture_ktx2-fps30-1k_baseColor_default" / "texture_0000000.ktx2"
    first.write_text("version https://git-lfs.github.com/spec/v1\noid sha256:ab12\nsize 4096\n")
    assert main(["check", str(cloned)]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"error: texture {first} is a Git LFS pointer, not the texture; fetch it with `git lfs pull`")
    assert "Traceback" not in err
