#!/usr/bin/env bash
# Can LIGGGHTS 3.8 carry a protected plate of mass M on a mount (issue #67 item 4)? Its primitive
# walls cannot move with the dynamics, so the plate here is a mesh (fix mesh/surface/stress) moved
# by fix move/mesh linear/variable at the velocity of one far-away atom of mass M (the plate's
# body, integrated by nve/sphere), which fix addforce pushes with the mesh's total force
# (f_ID[3]) and the mount's spring -k (z - z0). One steel sphere (5 mm radius, 1 m/s) strikes the
# plate (M = 2 m, e = 1, no friction), dt = 1e-8 s (the contact lasts about 3,000 steps).
# Against closed form: a free plate leaves with -2/3 m/s and the sphere rebounds at +1/3 m/s, with
# no energy gained; on a spring, the sphere's, the plate's and the spring's energy is conserved.
# Each run prints the sphere's and the plate's velocity after the blow and the energy after over
# before. Usage: bench/plate_on_liggghts.sh   (a few seconds; needs liggghts on PATH)
set -euo pipefail
source "$(dirname "$0")/common.sh"
cd "$work"
cat > plate.stl <<'EOF'
solid plate
facet normal 0 0 1
outer loop
vertex -0.02 -0.02 0
vertex 0.02 -0.02 0
vertex 0.02 0.02 0
endloop
endfacet
facet normal 0 0 1
outer loop
vertex -0.02 -0.02 0
vertex 0.02 0.02 0
vertex -0.02 0.02 0
endloop
endfacet
endsolid plate
EOF
# deck ID WHAT MOVES PLATE_FORCE MESH_VELOCITY MOUNT_K: MOVES 0 holds the plate still (a rigid
# wall). PLATE_FORCE: what pushes the body (-c_fwb: the wall's force on the spheres as store_force
# keeps it this step; f_plate[3]: the stress fix's total).
deck() {
  local what=$2 moves=$3 force=$4 velocity=$5 k=$6
  cat > "in.$1" <<EOF
atom_style granular
atom_modify map array sort 0 0.0
boundary f f f
newton off
communicate single vel yes
units si
hard_particles yes
region box block -0.05 0.05 -0.05 0.05 -0.05 0.05 units box
create_box 2 box
neighbor 0.0005 bin
neigh_modify delay 0
fix m1 all property/global youngsModulus peratomtype 2e11 2e11
fix m2 all property/global poissonsRatio peratomtype 0.3 0.3
fix m3 all property/global coefficientRestitution peratomtypepair 2 1 1 1 1
fix m4 all property/global coefficientFriction peratomtypepair 2 0 0 0 0
pair_style gran model hertz tangential history
pair_coeff * *
create_atoms 1 single 0.003 0.001 0.005001 units box
create_atoms 1 single 0.04 0.04 -0.04 units box
set atom 1 diameter 0.01 density 7800
set atom 2 diameter 0.01 density 15600
group ball id 1
group body id 2
velocity ball set 0 0 -1
fix integr all nve/sphere
fix plate all mesh/surface/stress file plate.stl type 2
fix wall all wall/gran model hertz tangential history mesh n_meshes 1 meshes plate store_force yes
compute fwb all reduce sum f_force_wall[3]
timestep 1e-8
variable zero equal 0
variable vb equal ${velocity}
variable fm equal ${force}-${k}*(z[2]+0.04)
EOF
  if [ "$moves" = 1 ]; then
    echo "fix mv all move/mesh mesh plate linear/variable v_zero v_zero v_vb" >> "in.$1"
    echo "fix push body addforce 0 0 v_fm" >> "in.$1"
  else
    echo "fix hold body setforce 0 0 0" >> "in.$1"
  fi
  cat >> "in.$1" <<EOF
variable v1 equal vz[1]
variable v2 equal vz[2]
variable e equal (0.5*mass[1]*vz[1]^2+0.5*mass[2]*vz[2]^2+0.5*${k}*(z[2]+0.04)^2)/(0.5*mass[1])
run 20000
print "result \${v1} \${v2} \${e}"
EOF
  liggghts -in "in.$1" -log "log.$1" > "screen.$1" || { tail -n 3 "screen.$1" >&2; exit 1; }
  awk -v name="$what" '/^result/ {printf "%-44s sphere %s m/s, plate %s m/s, energy after/before %s\n", name, $2, $3, $4}' "screen.$1"
}
deck held "plate held (a rigid wall)" 0 0 "0" 0
deck free "free plate" 1 -c_fwb "vz[2]" 0
deck spring "on a spring (1e6 N/m)" 1 -c_fwb "vz[2]" 1e6
deck lag "free, pushed by f_plate[3]" 1 "f_plate[3]" "vz[2]" 0
deck lag_fix "free, by f_plate[3], mesh at vz + dt fz / M" 1 "f_plate[3]" "vz[2]+dt*fz[2]/mass[2]" 0
