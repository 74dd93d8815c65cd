# Reference numbers for crates/io/tests/corpus.rs: independent topology counts on polygon faces (numpy + libigl only, no algesurf code).
# For each corpus OBJ: raw file and after welding (igl.remove_duplicate_vertices at 1e-9 * bbox
# diagonal, faces that repeat a vertex after welding dropped), V_used - E + F on the polygons,
# boundary edges, non-manifold vertices (fans = faces at v joined across edges with exactly two
# faces), and boundary loops counted on the fan-split mesh (one vertex copy per fan), where every
# boundary vertex has exactly two boundary edges so loops = components of the boundary-edge graph;
# components, per-component chi / loops / genus.
import sys, numpy as np, igl
from collections import defaultdict


def load_obj(path):
    V, F = [], []
    for line in open(path):
        t = line.split()
        if not t: continue
        if t[0] == 'v': V.append([float(x) for x in t[1:4]])
        elif t[0] == 'f':
            idx = [int(s.split('/')[0]) for s in t[1:]]
            F.append([i - 1 if i > 0 else len(V) + i for i in idx])
    return np.array(V), F

class UF:
    def __init__(s): s.p = {}
    def find(s, a):
        s.p.setdefault(a, a)
        while s.p[a] != a:
            s.p[a] = s.p[s.p[a]]; a = s.p[a]
        return a
    def union(s, a, b): s.p[s.find(a)] = s.find(b)
D = (sys.argv[1] if len(sys.argv) > 1 else '/work/shared/data').rstrip('/') + '/'

def edges_of(F):
    ef = defaultdict(list)
    for i, f in enumerate(F):
        for k in range(len(f)):
            a, b = f[k], f[(k + 1) % len(f)]
            ef[(min(a, b), max(a, b))].append(i)
    return ef

def split(F, ef):
    uf = UF()
    for (a, b), fs in ef.items():
        if len(fs) == 2:
            for v in (a, b): uf.union((v, fs[0]), (v, fs[1]))
    roots = defaultdict(set)
    for i, f in enumerate(F):
        for v in f: roots[v].add(uf.find((v, i)))
    nxt = max(roots) + 1 if roots else 0
    ids = {}
    S = []
    for i, f in enumerate(F):
        g = []
        for v in f:
            r = uf.find((v, i)); rs = sorted(roots[v])
            if r == rs[0]: g.append(v)
            else:
                if (v, r) not in ids: ids[(v, r)] = nxt; nxt += 1
                g.append(ids[(v, r)])
        S.append(g)
    nmv = sum(1 for r in roots.values() if len(r) > 1)
    return S, nmv

def loops_of(F):
    ef = edges_of(F)
    b = [e for e, fs in ef.items() if len(fs) == 1]
    uf = UF()
    for x, y in b: uf.union(x, y)
    # loop -> a face of it
    lf = {}
    for e in b: lf.setdefault(uf.find(e[0]), ef[e][0])
    return lf

def stats(tag, F, nv):
    ef = edges_of(F)
    used = {v for f in F for v in f}
    V, E, Fn = len(used), len(ef), len(F)
    bnd = sum(1 for fs in ef.values() if len(fs) == 1)
    nme = sum(1 for fs in ef.values() if len(fs) > 2)
    S, nmv = split(F, ef)
    lf = loops_of(S)  # faces keep their ids in S
    cu = UF()
    for fs in ef.values():
        for g in fs[1:]: cu.union(fs[0], g)
    comps = defaultdict(list)
    for i in range(Fn): comps[cu.find(i)].append(i)
    nloops = defaultdict(int)
    for f in lf.values(): nloops[cu.find(f)] += 1
    per = []
    for r, fs in comps.items():
        sub = [F[i] for i in fs]
        e2 = edges_of(sub)
        vv = len({v for f in sub for v in f})
        chi = vv - len(e2) + len(sub)
        per.append((len(sub), chi, nloops[r], sum(1 for x in e2.values() if len(x) == 1)))
    per.sort(key=lambda x: (-x[0], x))
    print(f"{tag}: V_used={V} E={E} F={Fn} chi={V-E+Fn} boundary_edges={bnd} boundary_loops={len(lf)} "
          f"components={len(comps)} nm_edges={nme} nm_vertices={nmv} unused={nv-V}")
    print(f"   components (F, chi, loops, boundary edges): {per[:20]}")

def run(name):
    Vx, F = load_obj(D + name)
    print(f"== {name}")
    stats("raw", F, len(Vx))
    diag = np.linalg.norm(Vx.max(0) - Vx.min(0))
    SV, SVI, SVJ, _ = igl.remove_duplicate_vertices(Vx, np.zeros((0, 3), dtype=np.int64), 1e-9 * diag)
    W = [[int(SVJ[v]) for v in f] for f in F]
    W = [f for f in W if len(set(f)) == len(f)]
    stats("welded", W, len(SV))
    S, _ = split(W, edges_of(W))
    stats("welded+split", S, max(v for f in S for v in f) + 1)

if __name__ == "__main__":
    for n in (sys.argv[2:] or ['cow.obj', 'fandisk.obj', 'spot.obj', 'stanford-bunny.obj', 'suzanne.obj', 'teapot.obj']):
        run(n)

# Usage: python corpus_reference.py [DATA_DIR [FILE.obj ...]]   (needs numpy and libigl)
