"""Summarise a library: its parameters, sequences, motions and motion graph.

A sequence whose parse was corrected by hand shows its corrections under it (``+F`` adds a
boundary or texton start at frame F, ``-F`` removes one, ``A>B`` moves one).

With --json the summary is one JSON object (schema: ``tvmedit.engine.store.library.INFO_SCHEMA``):
``format``, ``params``, ``sequences`` (name, frames, fps, clusters and textons as inclusive
0-based frame ranges, and ``corrections`` where corrected by hand), ``nodes`` (id, name,
sequence, start, end, texton_distance, intensity), ``edges`` of the graph (from, to, weight,
exit_frame, entry_frame, and ``added``: true for an edge put back so that every motion
reaches every other) and ``connect`` (mode, how many edges were added, their largest
weight, and why).
"""

import json
import math

from . import options

HELP = "summarise a library (add --json for a machine-readable summary)"


def add_arguments(parser):
    parser.add_argument("library", metavar="LIB", help="library directory")
    parser.add_argument("--json", action="store_true", help="print the summary as JSON")


def _least_sure(sequence, count=3):
    """The boundaries and textons of a sequence the parse is least sure of, lowest first."""
    items = [(c["confidence"], f"boundary at frame {c['start']}") for c in sequence["clusters"][1:]
             if c.get("confidence") is not None]
    items += [(t["confidence"], f"texton {_frames(t['start'], t['end'])}") for t in sequence["textons"]
              if t.get("confidence") is not None]
    return ", ".join(f"{what} {value:.2f}" for value, what in sorted(items, key=lambda i: i[0])[:count])


def _frames(start, end):
    return f"{start}-{end}"


def _read_as(manifest, name):
    """``; read as scvv, up -x, m`` where a sequence was not plain Z-up metre frames (``, facing
    +z`` where its front was given; ``, features in the capture's axes`` where it was built with
    ``--no-body-frame`` or its body had no frame of its own)."""
    from tvmedit.engine.capture.orientation import Orientation

    record = next(r for r in manifest["sequences"] if r["name"] == name)
    frame, fmt = record.get("orientation"), record.get("format", "ply")
    identity = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
    body = frame is None or frame.get("features", identity) != identity
    given = frame is not None and frame.get("reasons", {}).get("front") == "given"
    plain = frame is None or (frame["up"] == "+z" and frame["units"] == "m" and not frame["mirrored"] and body
                              and not given)
    if plain and fmt in ("ply", "obj", "off"):
        return ""
    return (f"; read as {fmt}" + ("" if frame is None else f", up {frame['up']}, {frame['units']}"
                                  + (f", facing {Orientation.from_json(frame).front}" if given else "")
                                  + (", mirrored" if frame["mirrored"] else "")
                                  + ("" if body else ", features in the capture's axes")))


def _corrections(entry):
    """``boundaries +140 -72 72>75; textons +300; representative at 305; drop t30/06``."""
    parts = []
    for kind in ("boundaries", "textons"):
        ops = entry.get(kind, {})
        marks = ([f"+{f}" for f in ops.get("add", [])] + [f"-{f}" for f in ops.get("remove", [])]
                 + [f"{a}>{b}" for a, b in ops.get("move", [])])
        if marks:
            parts.append(f"{kind} {' '.join(marks)}")
    if entry.get("representatives"):
        parts.append("representative at " + ", ".join(map(str, entry["representatives"])))
    if entry.get("drop"):
        parts.append("drop " + ", ".join(entry["drop"]))
    return "; ".join(parts)


def run(args):
    from tvmedit.engine.graph.database import advice
    from tvmedit.engine.store.library import Library

    library = Library.open(args.library)
    info = library.info()
    if args.json:
        print(json.dumps(info, indent=1))
        return 0
    params, manifest = info["params"], library.manifest
    bins = params["bins"]
    structure = ", ".join(f"{k}={v}" for k, v in params["structure"].items())
    print(f"library {library.path} (format {info['format']}, built by tvmedit {info['tvmedit']} "
          f"on {manifest.get('created', '?')})")
    print(f"parameters: bins r={bins['r'] * 100:g} cm, theta={math.degrees(bins['theta']):g} deg, "
          f"phi={math.degrees(bins['phi']):g} deg; {structure}; mu={params['mu']:g}")
    print(f"sequences ({len(info['sequences'])}):")
    for s in info["sequences"]:
        clusters = " ".join(_frames(c["start"], c["end"]) for c in s["clusters"])
        print(f"  {s['name']}: {s['frames']} frames at {s['fps']:g} fps, {len(s['clusters'])} clusters "
              f"[{clusters}], {len(s['textons'])} textons{_read_as(manifest, s['name'])}")
        if s.get("corrections"):
            print(f"    corrected by hand: {_corrections(s['corrections'])}")
        unsure = _least_sure(s)
        if unsure:
            print(f"    least sure (confidence 0-1): {unsure}")
    names = {n["id"]: n["name"] for n in info["nodes"]}
    width = max([len(name) for name in names.values()] + [4])
    print(f"motions ({len(info['nodes'])}):")
    print(f"  {'id':>3}  {'name':<{width}}  {'frames':<18} {'kind':<5} {'intensity':>9} {'d_T':>7}")
    for n in info["nodes"]:
        where = f"{n['sequence']} {_frames(n['start'], n['end'])}"
        intensity = "-" if n["intensity"] is None else f"{n['intensity']:.4f}"
        print(f"  {n['id']:>3}  {n['name']:<{width}}  {where:<18} {n.get('kind', 'cycle'):<5} {intensity:>9} "
              f"{n['texton_distance']:7.4f}")
    if any(n.get("kind") == "once" for n in info["nodes"]):
        print("  (once: a stretch that does not repeat, played through once; cycle: a texton played cyclically)")
    closed = [f"{n['name']} ({n['closing_frames']})" for n in info["nodes"] if n.get("closing_frames")]
    if closed:
        print(f"  loops closed, frames warped where the texton wraps: {', '.join(closed)}")
    hint = options.as_flags(advice(library.nodes))
    if hint:
        print(f"note: {hint}")
    connect = info["connect"]
    added = f", {connect['added']} of them added to connect it" if connect["added"] else ""
    print(f"graph: {len(info['edges'])} edges after pruning at mu={params['mu']:g}{added} "
          f"(connect {connect['mode']}: {connect['reason']})")
    natural = info.get("natural_step") or 0.0
    for e in info["edges"]:
        cut = f"  cut {e['jump'] / natural:.2f} natural steps" if natural and "jump" in e else ""
        blend = f", {e['blend_frames']} in-between" if e.get("blend_frames") else ""
        print(f"  {names[e['from']]:<{width}} -> {names[e['to']]:<{width}}  weight {e['weight']:.3f}  "
              f"exit {e['exit_frame']}  entry {e['entry_frame']}{cut}{blend}{'  (added)' if e['added'] else ''}")
    (low, high), (v, f) = library.bounds(), library.max_counts()
    size = sum(manifest["files"].values()) / 1e6
    print(f"stored: {manifest['counts']['stored_frames']} frames and "
          f"{manifest['counts'].get('blend_frames', 0)} in-between frames ({size:.0f} MB; natural step "
          f"{natural * 1000:.1f} mm), up to {v} vertices "
          f"and {f} triangles a frame, bounds {tuple(round(x, 2) for x in low)} to "
          f"{tuple(round(x, 2) for x in high)}")
    return 0
