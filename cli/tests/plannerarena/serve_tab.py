# Serves one tab of Planner Arena (its own module UI and server) on the given database.
import sys
from shiny import App, ui, reactive, run_app
from plannerarena.database import load_database
from plannerarena.performance import performance_ui, performance_server
from plannerarena.progress import progress_ui, progress_server
tab, db, port = sys.argv[1], sys.argv[2], int(sys.argv[3])
mods = {"performance": (performance_ui, performance_server), "progress": (progress_ui, progress_server)}
u, s = mods[tab]
def server(input, output, session):
    @reactive.calc
    def data():
        return load_database(db)
    s(tab, data)
run_app(App(ui.page_fluid(u(tab)), server), host="127.0.0.1", port=port)
