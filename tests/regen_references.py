"""Rewrite the reference images of tests/test_render.py after a deliberate change to the renderer.

    .venv/bin/python tests/regen_references.py

Look at the new images (and at ``git diff --stat tests/reference``) before committing them.
"""

import sys
from pathlib import Path

import imageio.v3 as iio

sys.path.insert(0, str(Path(__file__).resolve().parent))

from test_render import REFERENCE, reference_scenes  # noqa: E402

from tvmedit.player.context import headless_context  # noqa: E402


def main():
    ctx = headless_context()
    REFERENCE.mkdir(exist_ok=True)
    for name, scene in sorted(reference_scenes().items()):
        path = REFERENCE / f"{name}.png"
        iio.imwrite(path, scene(ctx))
        for stale in (path.with_suffix(".actual.png"), path.with_suffix(".diff.png")):
            stale.unlink(missing_ok=True)
        print(f"wrote {path.relative_to(REFERENCE.parent.parent)}")


if __name__ == "__main__":
    main()
