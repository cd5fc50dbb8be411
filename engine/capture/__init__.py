"""Reading captures as they come.

- :mod:`.load` opens a sequence (a folder, a glob, a manifest) and reads its frames;
- :mod:`.readers` maps file formats to readers (PLY, OBJ, OFF, Draco, glTF, scvv manifests),
  and :mod:`.writers` writes frames back in them; :mod:`.ktx2` reads a web player's KTX2
  textures, several frames to a file;
- :mod:`.plyfast` reads and writes binary PLY without a mesh library, and :mod:`.objfast` reads
  OBJ frames as exporters write them;
- :mod:`.orientation` finds which way is up and the units, and faces the front to the camera;
- :mod:`.normals` gives per-vertex normals.
"""
