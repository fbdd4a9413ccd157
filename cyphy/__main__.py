from cyphy.cli import run

run()
