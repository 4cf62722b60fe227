from dcf2bin.cli import main

if __name__ == "__main__":  # pragma: no cover
    main()
