#!/usr/bin/python3
"""The experiment registry (experiments.yaml) for the shell scripts: names,
one entry's field, or one row per entry. Usage: registry.py --help
(tactile_sweeps.registry.main)."""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "sweeps"))
from tactile_sweeps import registry  # noqa: E402

if __name__ == "__main__":
    sys.exit(registry.main())
