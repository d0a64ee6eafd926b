import sys

from flexcal.cli import main

sys.exit(main())
