# Which of an OBJ's triangles lie in closed, consistently wound components (positions welded
# by value): python3 closed.py ../../../../shared/scenes/sibenik/sibenik.obj
# (Sibenik: 343 components, 8 closed, 1524 of 80479 triangles, 1.9 %; 3830 degenerate once welded).
import sys, collections
pos=[]; key={}; vid=[]; tris=[]
for line in open(sys.argv[1]):
    if line.startswith('v '):
        p=tuple(float(x) for x in line.split()[1:4]); pos.append(p)
        vid.append(key.setdefault(p,len(key)))
    elif line.startswith('f '):
        idx=[vid[int(t.split('/')[0])-1] for t in line.split()[1:]]
        for i in range(1,len(idx)-1): tris.append((idx[0],idx[i],idx[i+1]))
P=[None]*len(key)
for p,k in key.items(): P[k]=p
print('triangles',len(tris),'welded verts',len(key))
de=collections.Counter()
for a,b,c in tris:
    for u,v in ((a,b),(b,c),(c,a)): de[(u,v)]+=1
# union-find over triangles sharing undirected edges
par=list(range(len(tris)))
def f(x):
    while par[x]!=x: par[x]=par[par[x]]; x=par[x]
    return x
owner={}
for t,(a,b,c) in enumerate(tris):
    for u,v in ((a,b),(b,c),(c,a)):
        e=(min(u,v),max(u,v))
        if e in owner: par[f(t)]=f(owner[e])
        else: owner[e]=t
comp=collections.defaultdict(list)
for t in range(len(tris)): comp[f(t)].append(t)
closed=0; closed_comps=0; negvol=0; degenerate=0
for r,ts in comp.items():
    ok=True; vol=0.0
    for t in ts:
        a,b,c=tris[t]
        if a==b or b==c or a==c: ok=False; degenerate+=1; continue
        for u,v in ((a,b),(b,c),(c,a)):
            if de[(u,v)]!=1 or de[(v,u)]!=1: ok=False
        A,B,C=P[a],P[b],P[c]
        vol+=(A[0]*(B[1]*C[2]-B[2]*C[1])-A[1]*(B[0]*C[2]-B[2]*C[0])+A[2]*(B[0]*C[1]-B[1]*C[0]))/6
    if ok:
        closed+=len(ts); closed_comps+=1
        if vol<0: negvol+=len(ts)
print('components',len(comp),'closed comps',closed_comps,'closed tris',closed, 'frac %.3f'%(closed/len(tris)),'neg-volume tris',negvol,'degenerate',degenerate)
sizes=sorted((len(t) for t in comp.values()),reverse=True)[:15]; print('largest comps',sizes)
