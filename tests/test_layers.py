"""The layering is enforced, not only documented: every import in the package, including
those inside functions, points to the importer's own package or a lower layer.

    physics -> effects -> model -> prediction -> fitting
      -> {identification, analysis, control} -> {io, rig} -> {synth, fleet, testing, workflow}
      -> monitor -> ros -> cli

(``_jit``, ``errors``, ``jsonable``, ``text``, ``pipes`` and ``__version__`` are below
everything, then ``files``; ``smoothing`` sits with physics; ``experiment``, the data type
every layer above the model passes around, sits with the model.)
"""
import ast
from pathlib import Path

import pneumatic_servo

LAYERS = (
    ('', '_jit', 'errors', '__version__', 'jsonable', 'text', 'pipes'),
    ('files',),
    ('physics', 'smoothing'),
    ('effects',),
    ('model', 'experiment'),
    ('prediction',),
    ('fitting',),
    ('identification', 'analysis', 'control'),
    ('io', 'rig'),
    ('synth', 'fleet', 'testing', 'workflow'),
    ('monitor',),
    ('ros',),
    ('cli',),
)
LAYER = {name: i for i, names in enumerate(LAYERS) for name in names}
ROOT = Path(pneumatic_servo.__file__).parent


def _module(path: Path) -> tuple[str, bool]:
    parts = ('pneumatic_servo',) + path.relative_to(ROOT).with_suffix('').parts
    if parts[-1] == '__init__':
        return '.'.join(parts[:-1]), True
    return '.'.join(parts), False


def _targets(node, module: str, is_package: bool) -> list[str]:
    if isinstance(node, ast.Import):
        return [a.name for a in node.names]
    if node.level:
        base = module.split('.') if is_package else module.split('.')[:-1]
        base = base[:len(base) - (node.level - 1)]
        prefix = '.'.join(base + ([node.module] if node.module else []))
    else:
        prefix = node.module or ''
    if node.module:
        return [prefix]
    return [f'{prefix}.{a.name}' for a in node.names]


def package_imports():
    """(importing file, line, importer's package, imported package) for every import of a
    pneumatic_servo module, at any depth of the syntax tree."""
    out = []
    for path in sorted(ROOT.rglob('*.py')):
        module, is_package = _module(path)
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if not isinstance(node, (ast.Import, ast.ImportFrom)):
                continue
            for target in _targets(node, module, is_package):
                if target == 'pneumatic_servo' or target.startswith('pneumatic_servo.'):
                    src = module.split('.')[1] if '.' in module else ''
                    dst = target.split('.')[1] if '.' in target else ''
                    out.append((path.relative_to(ROOT.parent), node.lineno, src, dst))
    return out


def test_every_package_has_a_layer():
    packages = {p.name for p in ROOT.iterdir() if (p / '__init__.py').exists()}
    modules = {p.stem for p in ROOT.glob('*.py') if p.stem != '__init__'}
    assert (packages | modules) - set(LAYER) == set()


def test_no_import_points_up_or_sideways():
    found = package_imports()
    assert len(found) > 100  # the walk sees the package's own imports
    wrong = [f'{path}:{line}: {src} imports {dst}' for path, line, src, dst in found
             if src != dst and (LAYER[dst] > LAYER[src]
                                or (LAYER[dst] == LAYER[src] and dst != ''))]
    assert not wrong, 'imports against the layers:\n' + '\n'.join(wrong)


def test_the_walk_sees_imports_inside_functions():
    """An import inside a function body (the demo loads rclpy only for its ROS stage) is one
    of the edges the layer test checks."""
    path = ROOT / 'cli' / 'demo.py'
    inner = [node.lineno for fn in ast.walk(ast.parse(path.read_text()))
             if isinstance(fn, ast.FunctionDef) for node in ast.walk(fn)
             if isinstance(node, ast.ImportFrom)]
    assert inner
    seen = {(p.name, line) for p, line, _, _ in package_imports()}
    assert all(('demo.py', line) in seen for line in inner)


def module_graph() -> dict[str, set[str]]:
    """Module -> the package's modules it imports (at any depth of its syntax tree; a name
    imported from a package counts as its submodule where one has that name)."""
    modules = {}
    for path in sorted(ROOT.rglob('*.py')):
        module, is_package = _module(path)
        modules[module] = (path, is_package)

    def known(target: str) -> str | None:  # the longest prefix that is a module
        parts = target.split('.')
        while parts and '.'.join(parts) not in modules:
            parts.pop()
        return '.'.join(parts) or None

    graph = {}
    for module, (path, is_package) in modules.items():
        edges = graph.setdefault(module, set())
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if not isinstance(node, (ast.Import, ast.ImportFrom)):
                continue
            targets = _targets(node, module, is_package)
            if isinstance(node, ast.ImportFrom) and node.module:
                targets += [f'{targets[0]}.{a.name}' for a in node.names]
            edges.update(t for t in map(known, targets) if t not in (None, module))
    return graph


def import_cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The cycles of ``graph``: its strongly connected parts of more than one module."""
    index, low, stack, cycles = {}, {}, [], []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        for w in graph.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            part = stack[stack.index(v):]
            del stack[stack.index(v):]
            if len(part) > 1:
                cycles.append(sorted(part))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return cycles


def test_no_import_cycle_inside_a_package():
    """Modules of one package import each other one way only (imports inside functions
    count: they still tie the two modules together)."""
    graph = module_graph()
    assert 'pneumatic_servo.ros.loop' in graph['pneumatic_servo.ros.recorder']
    assert import_cycles({'a': {'b'}, 'b': {'c'}, 'c': {'a'}, 'd': {'a'}}) == [['a', 'b', 'c']]
    cycles = import_cycles(graph)
    assert not cycles, 'import cycles:\n' + '\n'.join(' <-> '.join(c) for c in cycles)


def test_no_module_over_450_lines():
    """One module per idea: a module past 450 lines is doing several jobs (issue 18's
    limit; a module that must be longer says why here)."""
    root = Path(pneumatic_servo.__file__).parent
    long = {str(p.relative_to(root)): n for p in root.rglob('*.py')
            if (n := len(p.read_text().splitlines())) > 450}
    assert not long, f'modules over 450 lines: {long}'
