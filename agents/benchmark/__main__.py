from agents.benchmark.cli import main

main()
