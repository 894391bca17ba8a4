"""``python -m motionsig_cli`` runs the command-line tool."""

from motionsig_cli.cli.entry import main

raise SystemExit(main())
