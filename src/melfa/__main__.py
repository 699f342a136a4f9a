"""`python -m melfa` is the same as the `melfa` command."""

from melfa.cli import main

if __name__ == "__main__":
    main()
