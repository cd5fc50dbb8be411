"""The motion database and graph, and the edits made on them: sections 5-8, eq. (9)-(16).

- :mod:`.database`: one representative texton per cluster, eq. (9);
- :mod:`.motiongraph`: node distance, transitions, weights and pruning, eq. (10)-(14);
- :mod:`.connect`: the pruned graph made strongly connected;
- :mod:`.search`: best paths, eq. (15)-(16); :mod:`.timing`: legs of a given length;
- :mod:`.compose`: an edit as a frame schedule; :mod:`.export`: an edit written as frames.
"""
