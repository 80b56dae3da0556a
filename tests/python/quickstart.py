import mps2p

with mps2p.Scene(0.01) as scene:                       # particle spacing l0 = 0.01 m
    water = scene.add_fluid("water", 1000.0, 1e-6)     # density kg/m^3, viscosity m^2/s
    scene.add_fluid_box(water, 0.0, 0.0, 0.15, 0.3)    # corners (x0, y0), (x1, y1): a column 0.15 m x 0.3 m
    scene.add_tank(0.0, 0.0, 0.6, 0.7, open_top=True)  # walls around the box (0, 0) to (0.6, 0.7)
    solver = mps2p.Solver(scene)                       # copies the scene
solver.advance_to(0.2, progress=True)                  # to t = 0.2 s, with a progress bar
print("front at x = %.3f m after %d steps" % (solver.front(water, below=0.02), solver.step_count))
print(solver.positions().shape, "particles, walls too; max speed %.2f m/s" % solver.stat("max_speed"))
