"""Feature vectors and frame distance: spherical-coordinate histograms, section 3, eq. (1)-(4).

- :mod:`.histograms`: a frame's r, theta and phi histograms about an origin (eq. (1));
- :mod:`.vectors`: a sequence's rows, the origin that follows the person, and the frame
  distance between rows (eq. (2)-(4)).
"""

from .histograms import MAX_ANGLE_BINS, MAX_R_BINS, BinSizes, frame_histograms, spherical
from .vectors import (CENTRED_VERTICES, FOLLOW_M, SAMPLE_FRAMES, FeatureAccumulator, Features, centred_histograms,
                      distance_matrix, features_of, follow_picks, frame_distance, frame_origin, histogram_distance,
                      moves_across, spread_indices, stacked, stored_rows)

__all__ = ["BinSizes", "Features", "FeatureAccumulator", "frame_histograms", "centred_histograms", "stored_rows",
           "CENTRED_VERTICES", "stacked", "spherical", "features_of", "frame_origin", "moves_across", "FOLLOW_M",
           "SAMPLE_FRAMES", "follow_picks", "spread_indices", "frame_distance", "histogram_distance", "distance_matrix",
           "MAX_ANGLE_BINS", "MAX_R_BINS"]
