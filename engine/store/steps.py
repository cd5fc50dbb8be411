"""The display steps a library holds: the field of each step a schedule can show.

:mod:`tvmedit.engine.inbetween.instants` says what a step's field is;
:func:`tvmedit.engine.store.inbetweens.instant_library` makes them at build time and stores
them in ``instant_pairs.npy`` and ``instant_fields.npy`` (:mod:`tvmedit.engine.store.layout`).
:class:`DisplaySteps` reads them back for a :class:`tvmedit.engine.store.library.Library`,
memory-mapped, so the player and the renderer take a step's field as they take a frame.
"""

from functools import cached_property

from . import layout

__all__ = ["DisplaySteps"]


class DisplaySteps:
    """What a library adds for its display steps (a mix-in of ``Library``, which provides
    ``path``, ``manifest``, ``_locate``, ``_row`` and ``_blend_row``)."""

    @cached_property
    @layout.reads_format
    def _instants(self):
        """``({(from id, to id): (first, rows)}, fields)`` of the display steps, or None."""
        if "instant_pairs.npy" not in self.manifest.get("files", {}):
            return None
        table = layout.load_array(self.path, "instant_pairs.npy")
        fields = layout.load_array(self.path, "instant_fields.npy")
        if table.ndim != 2 or table.shape[1] != 4 or fields.ndim != 2 or fields.shape[1] != 3 or (
                len(table) and int((table[:, 2] + table[:, 3]).max()) > len(fields)):
            raise layout.damaged(self.path, ValueError("instant_pairs.npy does not match instant_fields.npy"))
        return {(a, b): (first, rows) for a, b, first, rows in table.tolist()}, fields

    @property
    def smooth(self):
        """Whether the library holds display-rate in-betweens (:meth:`instant_field`); a
        library built before them, or with ``smooth=False``, plays at the capture's rate."""
        return self._instants is not None

    def _mesh_id(self, key):
        """The id the display steps name mesh ``key`` by: its stored row, or ``-1 - row`` of an
        in-between frame."""
        sequence, frame, *blend = key
        if blend and blend[0] is not None:
            return -1 - self._blend_row(blend[0])
        return self._row(sequence, frame)

    @layout.reads_format
    def instant_field(self, key, next_key):
        """The float16 (N, 3) displacement that carries mesh ``key``'s N vertices onto mesh
        ``next_key``'s surface (:mod:`tvmedit.engine.inbetween.instants`): the surface at fraction
        ``s`` of the step is ``positions + s * field``. None where the library holds none for
        this step (built before them, or a step no schedule of it shows)."""
        if self._instants is None or next_key is None:
            return None
        found = self._instants[0].get((self._mesh_id(key), self._mesh_id(next_key)))
        if found is None:
            return None
        first, rows = found
        _, offsets, row, _ = self._locate(key)
        if rows != int(offsets[row, 1]):
            raise layout.damaged(self.path, ValueError(f"the display step from {key} has {rows} rows for "
                                                       f"{int(offsets[row, 1])} vertices"))
        return self._instants[1][first:first + rows]
