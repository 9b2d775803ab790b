"""`python -m railbrake`: the railbrake command line."""

from railbrake.cli import main

if __name__ == "__main__":
    main()
