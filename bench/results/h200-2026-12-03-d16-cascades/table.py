# Tables of docs/realtime.md ("16-bit cascades") from two raster.json of run.tgz:
#   python3 table.py BASE/raster.json NEW/raster.json
import json, re, sys
raster = ("cascades","shadow_maps","depth_prepass","visibility","gbuffer","forward")
def corrected(p):
    # The bench before its correction (bench_raster.cpp, this session) charged counted
    # rasterized triangles at the 1024² setup rate ("geometry"); the corrected bench bounds
    # them by the mixed and quad bounds it measured on the pass's own targets. Re-derived from
    # the same run: a pass bound by "geometry" takes the larger of its mixed and quad bounds.
    if p.get('bound') != 'geometry':
        return p
    parts = {}
    for w in p['work']:
        m = re.match(r'(mixed|quads) ([0-9.]+)', w)
        if m:
            parts[m.group(1)] = float(m.group(2))
    kind = max(parts, key=parts.get)
    q = dict(p)
    q['bound'], q['bound_ms'] = kind, parts[kind]
    q['ratio'] = p['median_ms'] / parts[kind]
    return q
def load(path):
    d=json.load(open(path)); out={}
    for f in d['frames']:
        m=re.search(r'/(\w+)-(\d+x\d+)-(\w+)-(every|cached)\.json', f['file'])
        f = dict(f)
        f['passes'] = [corrected(p) for p in f['passes']]
        out[m.groups()]=f
    return out
base, new = load(sys.argv[1]), load(sys.argv[2])
sizes=["960x540","1920x1080","3840x2160"]
for scene in ("sibenik","cornell"):
    print(f"\n{scene}: frame GPU ms, every / cached, base → new\n")
    print("| size | visibility | deferred | forward |\n| --- | --- | --- | --- |")
    for s in sizes:
        row=[s.replace('x','×')]
        for p in ("visibility","deferred","forward"):
            b=[base[(scene,s,p,k)]['frame_gpu_median_ms'] for k in ("every","cached")]
            n=[new[(scene,s,p,k)]['frame_gpu_median_ms'] for k in ("every","cached")]
            row.append(f"{b[0]:.3f} / {b[1]:.3f} → {n[0]:.3f} / {n[1]:.3f}")
        print("| "+" | ".join(row)+" |")
    print(f"\n{scene}: raster passes after (new), median ms / bound ms (ratio), maps every frame; the pipeline's own passes from its frame\n")
    print("| pass | "+" | ".join(x.replace('x','×') for x in sizes)+" |\n| --- | --- | --- | --- |")
    for pname in raster:
        row=[f"`{pname}`"]; any_=False
        for s in sizes:
            cells=[]
            for p in ("visibility","deferred","forward"):
                f=new[(scene,s,p,"every")]
                for q in f['passes']:
                    if q['name']==pname and q['depth']==0:
                        cells.append((p,q['median_ms'],q['bound_ms'],q['ratio'],q['bound']))
            if not cells: row.append("—"); continue
            any_=True
            rs=[c[3] for c in cells]; ms=[c[1] for c in cells]
            if pname in ("cascades","shadow_maps"):
                row.append(f"{min(ms):.3f}–{max(ms):.3f} / {cells[0][2]:.3f} ({min(rs):.2f}–{max(rs):.2f}, {cells[0][4]})")
            else:
                row.append(" ; ".join(f"{c[1]:.3f} / {c[2]:.3f} ({c[3]:.2f}, {c[4]})" for c in cells[:1]) + (f" [{len(cells)} frames {min(rs):.2f}–{max(rs):.2f}]" if len(cells)>1 else ""))
        if any_: print("| "+" | ".join(row)+" |")
    worst=max((q['ratio'],q['name'],k) for k,f in new.items() if k[0]==scene for q in f['passes'] if q['depth']==0 and q['name'] in raster)
    print(f"\nworst raster ratio ({scene}, every frame of the run): {worst[0]:.3f} {worst[1]} {worst[2]}")
