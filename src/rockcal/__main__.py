from rockcal.cli.app import main

main()
