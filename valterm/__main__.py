from valterm.cli import main

raise SystemExit(main())
