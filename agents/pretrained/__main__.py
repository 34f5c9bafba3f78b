"""``python -m agents.pretrained``: runs ``agents.pretrained.cli``."""

import sys

from agents.pretrained.cli import main

if __name__ == "__main__":
    main(sys.argv[1:])
