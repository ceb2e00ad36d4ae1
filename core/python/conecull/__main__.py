"""`python -m conecull ...`: the same commands as the `conecull` script."""

from conecull.app.cli import main

if __name__ == "__main__":
    raise SystemExit(main())
