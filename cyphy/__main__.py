import sys

from cyphy.cli import main

sys.exit(main())
