// Reading cmkit results files: query lines, each followed by its result line
// (what `cmkit view` writes), as in docs/query-format.md.

/** The key=value fields of a line, and its first bare word (the operation). */
export function parseFields(line) {
  const fields = {};
  let op = '';
  line.trim().split(/\s+/).forEach((token, i) => {
    const eq = token.indexOf('=');
    if (eq < 0) {
      if (i === 0) op = token;
    } else {
      fields[token.slice(0, eq)] = token.slice(eq + 1);
    }
  });
  return { op, fields };
}

function vec(text) {
  if (!text) return null;
  const v = text.split(',').map(Number);
  return v.length === 3 && v.every(Number.isFinite) ? v : null;
}

function isQueryLine(line) {
  const first = line.trim().split(/\s+/)[0];
  return first.length > 0 && !first.includes('=');
}

/**
 * Parses a results file into trace records:
 * {index, query, result, op, start, end, fraction, endpos, type, point, normal,
 *  contents, modelFeature, trmFeature, entity, error}; entity is the entity
 *  hit of a world result (`cmkit query --world`), else ''.
 */
export function parseResults(text) {
  const lines = text.split('\n').map((l) => l.trim()).filter((l) => l && !l.startsWith('#'));
  const records = [];
  for (let i = 0; i < lines.length; ++i) {
    if (!isQueryLine(lines[i])) continue;
    const query = lines[i];
    const result = i + 1 < lines.length && !isQueryLine(lines[i + 1]) ? lines[++i] : '';
    const q = parseFields(query);
    const r = parseFields(result).fields;
    const start = vec(q.fields.start) ?? vec(q.fields.pos);
    let end = vec(q.fields.end) ?? start;
    if (q.op === 'contacts' && start && vec(q.fields.dir)) {
      const d = vec(q.fields.dir);
      const depth = Number(q.fields.depth) || 0;
      end = start.map((s, k) => s + d[k] * depth);
    }
    const sfx = r.type !== undefined ? '' : '.0';
    records.push({
      index: records.length,
      query,
      result,
      op: q.op,
      start,
      end,
      fraction: r.fraction !== undefined ? Number(r.fraction) : null,
      endpos: vec(r.endpos) ?? end,
      type: r['type' + sfx] ?? 'none',
      point: vec(r['point' + sfx]),
      normal: vec(r['normal' + sfx]),
      contents: r['contents' + sfx] ?? r.contents ?? '',
      modelFeature: r['modelfeature' + sfx] ?? '',
      trmFeature: r['trmfeature' + sfx] ?? '',
      entity: r['entity' + sfx] ?? r.entity ?? '',
      error: r.error ?? (result ? '' : 'no result line'),
    });
  }
  return records;
}

/** A human-readable description of a record's contact. */
export function describe(rec) {
  const f = (v) => (v ? v.map((x) => +Number(x).toFixed(3)).join(', ') : '-');
  const lines = [`#${rec.index} ${rec.op}`, rec.query];
  if (rec.error) {
    lines.push(`error: ${rec.error}`);
    return lines.join('\n');
  }
  lines.push(
    `fraction: ${rec.fraction ?? '-'}`,
    `end position: ${f(rec.endpos)}`,
    `contact: ${rec.type}`,
    `point: ${f(rec.point)}`,
    `normal: ${f(rec.normal)}`,
    `contents: ${rec.contents}`,
    `feature: model ${rec.modelFeature}, trace model ${rec.trmFeature}`,
  );
  if (rec.entity) lines.push(`entity: ${rec.entity}`);
  return lines.join('\n');
}
