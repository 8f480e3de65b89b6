"""The elastic cantilever of options/cantilever.opts by finite elements, with CalculiX (Debian calculix-ccx):
a 1.0 x 0.1 x 0.1 m beam of C3D8I bricks (incompatible modes, accurate in bending), clamped at x = 0 where
the scene's support block ends, the 10 kN tip load spread over the end face as the scene's force region
spreads it over its nodes (bilinear face weights: uniform traction). Returns the end face's mean
deflection, the quantity pdimplicit reports for the force region."""
import os
import shutil
import subprocess
import tempfile


def weight(n, i):
    return 0.5 if i in (0, n) else 1.0


def deflection(nx, ny, nz, L=1.0, b=0.1, h=0.1, E=30e9, nu=0.25, P=1e4):
    if not shutil.which("ccx"):
        subprocess.run(["apt-get", "install", "-y", "calculix-ccx"], check=True, capture_output=True)
    work = tempfile.mkdtemp(prefix="pdfe_")

    def nid(i, j, k):
        return 1 + i + (nx + 1) * (j + (ny + 1) * k)

    face = [(j, k) for k in range(nz + 1) for j in range(ny + 1)]
    total = sum(weight(ny, j) * weight(nz, k) for j, k in face)
    with open(os.path.join(work, "cant.inp"), "w") as f:
        f.write("*NODE\n")
        for k in range(nz + 1):
            for j in range(ny + 1):
                for i in range(nx + 1):
                    f.write("%d,%.12g,%.12g,%.12g\n" % (nid(i, j, k), L * i / nx, b * j / ny, h * k / nz))
        f.write("*ELEMENT,TYPE=C3D8I,ELSET=EALL\n")
        e = 1
        for k in range(nz):
            for j in range(ny):
                for i in range(nx):
                    n = [nid(i, j, k), nid(i + 1, j, k), nid(i + 1, j + 1, k), nid(i, j + 1, k), nid(i, j, k + 1), nid(i + 1, j, k + 1),
                         nid(i + 1, j + 1, k + 1), nid(i, j + 1, k + 1)]
                    f.write("%d,%s\n" % (e, ",".join(map(str, n))))
                    e += 1
        f.write("*NSET,NSET=TIP\n" + "".join("%d\n" % nid(nx, j, k) for j, k in face))
        f.write("*MATERIAL,NAME=C\n*ELASTIC\n%.12g,%.12g\n*SOLID SECTION,ELSET=EALL,MATERIAL=C\n" % (E, nu))
        f.write("*STEP\n*STATIC\n*BOUNDARY\n" + "".join("%d,1,3\n" % nid(0, j, k) for j, k in face))
        f.write("*CLOAD\n" + "".join("%d,3,%.15g\n" % (nid(nx, j, k), -P * weight(ny, j) * weight(nz, k) / total) for j, k in face))
        f.write("*NODE PRINT,NSET=TIP\nU\n*END STEP\n")
    subprocess.run(["ccx", "-i", "cant"], cwd=work, check=True, capture_output=True, env=dict(os.environ, OMP_NUM_THREADS="1"))
    u, table = {}, False
    for line in open(os.path.join(work, "cant.dat")):
        t = line.split()
        if "displacements" in line:
            table = True
        elif table and len(t) == 4:
            u[int(t[0])] = float(t[3])
    shutil.rmtree(work)
    return -sum(weight(ny, j) * weight(nz, k) * u[nid(nx, j, k)] for j, k in face) / total
