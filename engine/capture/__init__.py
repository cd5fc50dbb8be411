"""Reading captures as they come.

- :mod:`.load` opens a sequence (a folder, a glob, a manifest) and reads its frames;
- :mod:`.readers` maps file formats to readers (PLY, OBJ, OFF, Draco, glTF, scvv manifests);
- :mod:`.plyfast` reads and writes binary PLY without a mesh library;
- :mod:`.orientation` finds which way is up, the units and the front;
- :mod:`.normals` gives per-vertex normals.
"""
