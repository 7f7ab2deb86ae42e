"""``python -m rubberfriction`` is the ``rubberfriction`` command."""

from rubberfriction.driver.cli.main import main

raise SystemExit(main())
