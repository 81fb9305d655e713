"""shipthermal: finite-volume thermal solver for ships."""
