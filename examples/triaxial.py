# Triaxial compression of CT-scanned sand grains' clumps in YADE, with yade_mss.studies.triaxial: three grains
# from CT volumes as templates (exact mass and inertia each), a periodic cell of their clumps at random
# orientations, isotropic compaction to 100 kPa, then drained shearing (constant lateral stress) at an inertial
# number of 5e-4. Prints the curve (compression positive) and what it gives: friction and dilatancy angles,
# E50, the void ratio on the grains' exact volumes and on the clumps' own.
# Run: yade -n -x examples/triaxial.py        (MSS_SHORT=1 for a short run; MSS_FIGURES=DIR for a picture)
import os

from yade_mss import mssTemplate, triaxial

short = os.environ.get('MSS_SHORT') == '1'
data = os.environ.get('MSS_DATA', os.path.join('tests', 'data'))

# Grains about 2 mm across, 12 spheres each (SI units)
grains = [dict(source=os.path.join(data, 'grain_voxels_155x157x167.npy'), voxelSize=2e-3 / 160),
          dict(source=os.path.join(data, 'two_grains_labels.npy'), voxelSize=2e-3 / 60, label=1),
          dict(source=os.path.join(data, 'two_grains_labels.npy'), voxelSize=2e-3 / 70, label=2)]
templates = [mssTemplate(g.pop('source'), nSpheres=12, contacts=False, **g) for g in grains]
for t in templates:
    print('template  %s' % t)

r = triaxial(templates, grains=40 if short else 200, confining=100e3, strain=0.02 if short else 0.15,
             state='dense', seed=1, density=2650, young=1e8, frictionAngle=0.5)
c = r.compaction
print('compacted in %d steps to p = %.4g Pa: void ratio %.3f (on the clumps\' own volumes %.3f)'
      % (c['steps'], c['p_Pa'], c['void_ratio'], c['void_ratio_union']))
print('%8s %8s %10s %10s %7s %6s' % ('strain', 'eps_v', 'p (Pa)', 'q (Pa)', 'q/p', 'Z'))
for row in r.records[::max(1, len(r.records) // 10)] + r.records[-1:]:
    print('%8.4f %8.4f %10.4g %10.4g %7.3f %6.2f' % (row['axial_strain'], row['volumetric_strain'], row['p_Pa'],
                                                     row['q_Pa'], row['q_over_p'], row['coordination']))
d = r.derived
print('phi_peak %.1f deg at strain %.3f, phi_cs %.1f deg, psi_max %.1f deg, E50 %.3g Pa, e0 %.3f, I_max %.2g (%s)'
      % (d['phi_peak_deg'], d['strain_at_peak'], d['phi_cs_deg'], d['psi_max_deg'], d['E50_Pa'], d['e0'],
         d['I_max'], 'quasi-static' if d['quasi_static'] else 'NOT quasi-static'))
print('cost: %d steps of %.3g s (dt %.3g s), %d spheres, %.1f s' % (r.cost['steps'], r.cost['step_s'],
                                                                     r.cost['dt_s'], r.cost['spheres'],
                                                                     r.cost['wall_s']))
if not (d['quasi_static'] and r.records[-1]['axial_strain'] >= (0.02 if short else 0.15)):
    raise SystemExit('the test was not quasi-static or stopped short of its strain')
if os.environ.get('MSS_FIGURES'):  # the sheared specimen from the side, and its curves
    from yade_mss.pictures import sideView
    members = [(b.clumpId, b.id) for b in O.bodies if b is not None and b.isClumpMember]

    def curves(ax):
        e = [100 * x['axial_strain'] for x in r.records]
        ax.plot(e, [x['q_over_p'] for x in r.records], label='q/p')
        ax.plot(e, [100 * x['volumetric_strain'] for x in r.records], label='volumetric strain (%)')
        ax.set_xlabel('axial strain (%)')
        ax.legend()
        ax.set_title('drained triaxial compression, 100 kPa')
    sideView([tuple(O.bodies[i].state.pos) for c, i in members], [O.bodies[i].shape.radius for c, i in members],
             [c for c, i in members], os.path.join(os.environ['MSS_FIGURES'], 'triaxial.png'),
             'clumps of CT-scanned grains in a periodic cell, sheared', extra=curves)
