"""``python -m rubberfriction`` is the ``rubberfriction`` command."""

from rubberfriction.driver.cli import main

raise SystemExit(main())
