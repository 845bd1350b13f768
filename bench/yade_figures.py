# Figures of the YADE layer (issue: mssClump mass properties): run  yade -n -x bench/yade_figures.py
import math
import os

import numpy as np
import yade.minieigenHP as me
from yade_mss import generate, mssClump

data = os.environ.get('MSS_DATA', os.path.join('tests', 'data'))
O.materials.append(FrictMat(density=2000))


def rot(q):
    m = q.toRotationMatrix()
    return np.array([[m[i, j] for j in range(3)] for i in range(3)])


r = generate(os.path.join(data, 'ellipsoid_2_1_1.stl'), nSpheres=10, resolution=103)
cid, _ = mssClump(r)
st = O.bodies[cid].state
M = 2000 * 4 / 3 * math.pi * 2
exact = np.array([2, 5, 5]) * M / 5
mom = np.sort(np.array(st.inertia))
axis = rot(st.ori)[:, int(np.argmin(np.array(st.inertia)))]
print('ellipsoid, mass=target: mass error %.4f%%, principal moment errors %s%%, long axis off by %.2e degrees'
      % (100 * (st.mass - M) / M, np.array2string(100 * (mom - exact) / exact, precision=4),
         math.degrees(math.acos(min(1, abs(axis[0]))))))
cid, _ = mssClump(r, mass='union')
u = r.unionMass(resolution=400)
st = O.bodies[cid].state
print('ellipsoid, mass=union: mass vs union at 400 voxels: %.4f%%' % (100 * (st.mass - 2000 * u.volume) / (2000 * u.volume)))

f = generate(os.path.join(data, 'human_femur.stl'), nSpheres=70, resolution=103)
cid, _ = mssClump(f)
O.engines = [ForceResetter(), NewtonIntegrator(damping=0, gravity=(0, 0, 0))]
st = O.bodies[cid].state
I = 2000 * f.targetMass.inertia
w0 = np.array([0.3, -0.2, 0.5])
L0 = I.dot(w0)
st.angMom = me.Vector3(*L0)
O.dt = 1e-4
O.run(1001, True)
R = rot(st.ori)
L = R.dot(np.diag(np.array(st.inertia))).dot(R.T).dot(np.array(st.angVel))
print('femur free rotation, 1000 steps: |angMom - L0|/|L0| = %.2e, |I omega - L0|/|L0| = %.2e (dt %.0e)'
      % (np.linalg.norm(np.array(st.angMom) - L0) / np.linalg.norm(L0), np.linalg.norm(L - L0) / np.linalg.norm(L0), O.dt))
