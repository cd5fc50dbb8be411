"""The parser's accuracy on the development suite: ``python benchmarks/accuracy.py --help``.

The suite, the cross-validation and the bootstrap live in :mod:`tvmedit.engine.lab.accuracy`.
"""

import sys

from tvmedit.engine.lab.accuracy import main

if __name__ == "__main__":
    sys.exit(main())
