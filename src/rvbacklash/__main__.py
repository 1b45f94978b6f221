from rvbacklash.cli import main

main()
