#!/usr/bin/env python3
# Counts the SPIR-V operations of a kernel's traversal loop per path through its body (issue 21,
# fourteenth sitting): spirv-dis output of a specialised, optimised kernel (spirv-opt
# --set-spec-const-default-value ... --freeze-spec-const -O). The loop taken is the one whose body
# holds the most instructions and loads a storage buffer. Paths run from the loop header back to it
# (or out through the merge); per path: storage/uniform loads, local (stack) loads and stores, ALU
# operations (arithmetic, logic, compares, selects, conversions, bit ops), address computations
# (OpAccessChain), composite moves, conditional branches.
# ckern8_loopops.py (issue 18, ckern8): issue21_s15_loopops.py with the paths grouped also by their node loads.
# issue21_s15_loopops.py (fifteenth sitting): the same, with PICK (environment, an opcode such as
# OpBitCount): the smallest loop whose body holds PICK and a stack store (the octree walk of a trace.comp
# kernel, which after the specialisation below is one of several loops); without PICK the s14 rule.
import re, sys
from collections import defaultdict

def parse(path):
    ptr_sc = {}
    var_sc = {}
    blocks, order = {}, []
    cur = None
    for line in open(path):
        line = line.split(';')[0].strip()
        if not line: continue
        m = re.match(r'(%\S+) = OpTypePointer (\w+) ', line)
        if m: ptr_sc[m.group(1)] = m.group(2)
        m = re.match(r'(%\S+) = OpVariable (%\S+) (\w+)', line)
        if m: var_sc[m.group(1)] = m.group(3)
        m = re.match(r'(%\S+) = OpLabel', line)
        if m:
            cur = m.group(1); blocks[cur] = []; order.append(cur); continue
        if line.startswith('OpFunctionEnd'): cur = None; continue
        if cur is not None: blocks[cur].append(line)
    return ptr_sc, var_sc, blocks, order

def succ(ins):
    last = ins[-1]
    if last.startswith('OpBranchConditional'): return re.findall(r'%\S+', last)[1:3]
    if last.startswith('OpBranch '): return [last.split()[1]]
    if last.startswith('OpSwitch'): return re.findall(r'%\S+', last)[1::1][1::2] + [re.findall(r'%\S+', last)[1]]
    return []

def classify(ins, ptr_sc, var_sc, ac_sc):
    c = defaultdict(int)
    for l in ins:
        m = re.match(r'(%\S+) = (Op\w+)(.*)', l)
        op = m.group(2) if m else l.split()[0]
        rest = m.group(3) if m else l
        if op in ('OpPhi', 'OpLoopMerge', 'OpSelectionMerge', 'OpBranch', 'OpLine', 'OpNoLine', 'OpUnreachable', 'OpReturn', 'OpReturnValue'): continue
        if op == 'OpAccessChain' or op == 'OpInBoundsAccessChain':
            toks = rest.split()
            ac_sc[m.group(1)] = ptr_sc.get(toks[0], '?')
            c['addr'] += 1; continue
        if op == 'OpLoad':
            p = rest.split()[1]
            sc = var_sc.get(p) or ac_sc.get(p, '?')
            c['load ' + ('mem' if sc == 'StorageBuffer' else 'ubo' if sc == 'Uniform' else 'local')] += 1; continue
        if op == 'OpStore':
            p = rest.split()[0]
            sc = var_sc.get(p) or ac_sc.get(p, '?')
            c['store ' + ('mem' if sc in ('StorageBuffer', 'Uniform') else 'local')] += 1; continue
        if op == 'OpBranchConditional': c['cond branch'] += 1; continue
        if op in ('OpCompositeExtract', 'OpCompositeConstruct', 'OpCopyObject', 'OpVectorShuffle'): c['composite'] += 1; continue
        c['alu'] += 1
        c['op ' + op] += 1
    return c

def main():
    ptr_sc, var_sc, blocks, order = parse(sys.argv[1])
    ac_sc = {}
    # loops: the innermost (smallest) one that loads a storage buffer
    best = None
    cnt0 = {x: classify(blocks[x], ptr_sc, var_sc, ac_sc) for x in order}
    cnt0 = {x: classify(blocks[x], ptr_sc, var_sc, ac_sc) for x in order}
    for b in order:
        for l in blocks[b]:
            m = re.match(r'OpLoopMerge (%\S+) (%\S+)', l)
            if not m: continue
            merge, cont = m.group(1), m.group(2)
            body, st = set(), [b]
            while st:
                x = st.pop()
                if x in body or x == merge: continue
                body.add(x)
                for y in succ(blocks[x]):
                    if y != b: st.append(y)
            size = sum(len(blocks[x]) for x in body)
            if not any(cnt0[x]['load mem'] for x in body): continue
            if not any(l.startswith('OpLoopMerge') for x in body if x != b for l in blocks[x]) and size < 40: continue
            pick = __import__('os').environ.get('PICK')
            if pick and not (any(pick in l for x in body for l in blocks[x]) and any('OpStore' in l for x in body for l in blocks[x])): continue
            if best is None or size < best[0]: best = (size, b, merge, cont, body)
    size, head, merge, cont, body = best
    # counts per block (the access chains' storage classes need a pass in order)
    cnt = {x: classify(blocks[x], ptr_sc, var_sc, ac_sc) for x in order}
    cnt = {x: classify(blocks[x], ptr_sc, var_sc, ac_sc) for x in order}
    # paths header -> header (back edge) or -> merge / out
    paths = []
    def walk(x, seen, acc):
        if len(paths) > 5000: return
        tot = defaultdict(int, acc)
        for k, v in cnt[x].items(): tot[k] += v
        nxt = succ(blocks[x])
        ends = []
        for y in nxt:
            if y == head or y == cont: paths.append(('loop', seen + [x], tot)); continue
            if y not in body: paths.append(('exit', seen + [x], tot)); continue
            if y in seen: continue
            walk(y, seen + [x], tot)
        if not nxt: paths.append(('exit', seen + [x], tot))
    walk(head, [], {})
    # the continue block's own operations belong to every iteration
    for kind, p, t in paths:
        if kind == 'loop' and cont != head:
            for k, v in cnt[cont].items(): t[k] += v
    keys = ['load mem', 'load ubo', 'load local', 'store local', 'alu', 'addr', 'composite', 'cond branch']
    tot = defaultdict(int)
    for x in body:
        for k, v in cnt[x].items(): tot[k] += v
    print('%s: loop at %s, %d blocks, %d instructions; whole body: %s' % (sys.argv[1], head, len(body), size, ', '.join('%s %d' % (k, tot[k]) for k in keys)))
    # iterations: a push stores the stack or reloads none (the fetch's flag cleared), a pop loads the
    # stack; group the back-edge paths by (stack store, stack load) and give min..max per column
    groups = defaultdict(list)
    for kind, p, t in paths:
        if kind != 'loop': continue
        g = ("pop" if t["load local"] else ("push" if t["store local"] else "push/advance")) + ", %d node loads" % t["load mem"]
        groups[g].append(t)
    print('  iterations (paths back to the loop top; min-max over the paths of a kind):')
    print('  %-14s' % 'kind' + ' '.join('%12s' % k for k in keys) + '  paths')
    for g, ts in sorted(groups.items()):
        print('  %-14s' % g + ' '.join('%12s' % ('%d-%d' % (min(t[k] for t in ts), max(t[k] for t in ts))) for k in keys) + '  %d' % len(ts))
    if len(sys.argv) > 2:
        # the ALU opcodes of the path of each kind with the fewest ALU operations (and a node load)
        for g, ts in sorted(groups.items()):
            t = min(ts, key=lambda t: (-t['load mem'], t['alu']))
            print('  %s, fewest ALU operations (%d): %s' % (g, t['alu'], ' '.join('%s %d' % (k[5:], v) for k, v in sorted(t.items()) if k.startswith('op ') and v)))

main()
