from nav_bench.cli import main

raise SystemExit(main())
