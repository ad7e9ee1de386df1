// Cross-checks voxgi's glTF loader against the Khronos glTF-Validator (run by
// tools/gltf-validate, which installs the validator; see README, "glTF validity").
//
// usage: node tools/gltf_validate.js VOXGI FILE...
//
// For every file: the validator's errors (severity 0), each sorted into a part voxgi
// reads or one it does not (readPart below, the same definition as the loader's
// validateDocument), and `VOXGI check FILE`. It asserts:
//   - a file with a validator error in a part voxgi reads is refused: exit 1 and one
//     line "voxgi: error: FILE: ...";
//   - a sample (not in tests/data/malformed, or in its valid/ folder) with no such
//     error loads: exit 0.
// Corpus files the validator passes may still be refused: those are voxgi's own
// limits (texture size, float range, sampler values), listed as "voxgi only".
'use strict';

const fs = require('fs');
const path = require('path');
const { spawn } = require('child_process');
const os = require('os');
const validator = require('gltf-validator');

// Errors the validator reports in parts voxgi reads that voxgi accepts on purpose,
// each with the reason. Anything not listed here and in a read part must be refused.
const TOLERATED = [
  {
    code: 'VALUE_NOT_IN_RANGE',
    pointer: /^\/materials\/\d+\/emissiveFactor\/\d$/,
    when: (doc, p) => valueAt(doc, p) > 1,
    why: 'emissiveFactor above 1: HDR emission as exporters wrote it before ' +
         'KHR_materials_emissive_strength (scenes/cornell_box)',
  },
  {
    code: /^ACCESSOR_(NON_UNIT|INVALID_FLOAT)$/,
    pointer: /^\/accessors\/\d+/,
    when: (doc, p, roles) => onlyRoles(roles, p, ['NORMAL']),
    why: 'NORMAL data: voxgi normalises it and repairs zero or NaN normals (a warning)',
  },
  {
    code: 'NODE_MATRIX_TRS',
    pointer: /^\/nodes\/\d+\/matrix$/,
    when: () => true,
    why: 'matrix and TRS together: tinygltf keeps the matrix and drops the TRS before ' +
         'voxgi sees the node, so the matrix is used',
  },
];

function valueAt(doc, pointer) {
  let v = doc;
  for (const key of pointer.split('/').slice(1)) v = v == null ? undefined : v[key];
  return v;
}

function onlyRoles(roles, pointer, allowed) {
  const r = roles.accessors.get(Number(pointer.split('/')[2])) || new Set();
  return r.size > 0 && [...r].every((x) => allowed.includes(x));
}

// The texture slots voxgi reads of material m, as [name, textureInfo] pairs: every
// slot, the emissive one only where the material emits (as the loader reads it).
function textureSlots(m) {
  const slots = [];
  const pbr = m.pbrMetallicRoughness || {};
  const add = (name, info) => { if (info && typeof info === 'object') slots.push([name, info]); };
  add('baseColorTexture', pbr.baseColorTexture);
  add('metallicRoughnessTexture', pbr.metallicRoughnessTexture);
  if ((m.emissiveFactor || []).some((v) => v !== 0)) add('emissiveTexture', m.emissiveTexture);
  add('normalTexture', m.normalTexture);
  add('occlusionTexture', m.occlusionTexture);
  return slots;
}

// The TEXCOORD_n sets a primitive with material index `mi` reads: those its
// material's texture slots name (KHR_texture_transform's texCoord overrides the
// slot's), or set 0 without any.
function texCoordSets(doc, mi) {
  const m = Number.isInteger(mi) ? (doc.materials || [])[mi] : undefined;
  const sets = new Set();
  for (const [, info] of m ? textureSlots(m) : []) {
    const ext = (info.extensions || {}).KHR_texture_transform || {};
    const set = Number.isInteger(ext.texCoord) ? ext.texCoord : info.texCoord;
    sets.add(Number.isInteger(set) ? set : 0);
  }
  if (sets.size === 0) sets.add(0);
  return sets;
}

// The vertex attributes voxgi reads of a primitive.
function readAttributes(doc, p) {
  const names = ['POSITION', 'NORMAL', 'COLOR_0', 'TANGENT'];
  for (const set of texCoordSets(doc, p.material)) names.push(`TEXCOORD_${set}`);
  return names;
}

// What voxgi reads of a document: the accessors (with the roles they are read as),
// textures, images and samplers reachable from what it draws.
function readRoles(doc) {
  const accessors = new Map();
  const add = (i, role) => {
    if (!Number.isInteger(i)) return;
    if (!accessors.has(i)) accessors.set(i, new Set());
    accessors.get(i).add(role);
  };
  for (const m of doc.meshes || [])
    for (const p of m.primitives || []) {
      for (const a of readAttributes(doc, p))
        if (p.attributes && a in p.attributes) add(p.attributes[a], a);
      if ('indices' in p) add(p.indices, 'indices');
    }
  for (const a of doc.animations || [])
    for (const c of a.channels || []) {
      const s = (a.samplers || [])[c.sampler];
      if (!s || !c.target || c.target.path === 'weights') continue;
      add(s.input, 'animation input');
      add(s.output, 'animation output');
    }
  const textures = new Set();
  for (const m of doc.materials || [])
    for (const [, info] of textureSlots(m))
      if (Number.isInteger(info.index)) textures.add(info.index);
  const images = new Set(), samplers = new Set();
  for (const t of textures) {
    const tex = (doc.textures || [])[t] || {};
    if (Number.isInteger(tex.source)) images.add(tex.source);
    if (Number.isInteger(tex.sampler)) samplers.add(tex.sampler);
  }
  return { accessors, textures, images, samplers };
}

const NODE_FIELDS = ['children', 'mesh', 'camera', 'matrix', 'translation', 'rotation', 'scale'];
const PRIMITIVE_FIELDS = ['indices', 'material', 'mode'];
const MATERIAL_FIELDS = ['emissiveFactor', 'alphaMode', 'alphaCutoff', 'doubleSided',
  'emissiveTexture', 'normalTexture', 'occlusionTexture'];
const PBR_FIELDS = ['baseColorFactor', 'metallicFactor', 'roughnessFactor', 'baseColorTexture',
  'metallicRoughnessTexture'];

// Whether the error at `pointer` (a JSON pointer, or none for the container) lies in
// a part voxgi reads; with the reason when it does not.
function readPart(doc, roles, m) {
  const p = m.pointer;
  if (!doc || p === undefined || p === '' || p === '/') return { read: true };
  const k = p.split('/').slice(1);
  const index = Number(k[1]);
  switch (k[0]) {
    case 'asset': case 'extensionsRequired': case 'scene': case 'scenes':
    case 'bufferViews': case 'buffers': case 'cameras': case 'animations':
      return { read: true };
    case 'nodes':
      if (k.length < 3 || NODE_FIELDS.includes(k[2])) return { read: true };
      if (k[2] === 'extensions' && k[3] === 'KHR_lights_punctual') return { read: true };
      return { read: false, why: 'node field voxgi does not read (skin, weights)' };
    case 'meshes': {
      if (k[2] !== 'primitives') return { read: false, why: 'morph weights are not read' };
      if (k.length < 5 || PRIMITIVE_FIELDS.includes(k[4])) return { read: true };
      if (k[4] === 'attributes') {
        // Every attribute's accessor index is checked; only these are read.
        const prim = (((doc.meshes || [])[index] || {}).primitives || [])[Number(k[3])] || {};
        if (k.length < 6 || readAttributes(doc, prim).includes(k[5]) ||
            m.code === 'UNRESOLVED_REFERENCE')
          return { read: true };
        return { read: false, why: 'attribute voxgi does not read' };
      }
      return { read: false, why: 'morph targets are not read' };
    }
    case 'accessors':
      return roles.accessors.has(index) ? { read: true }
        : { read: false, why: 'accessor no read attribute, index or animation uses' };
    case 'materials':
      if (k.length < 3 || MATERIAL_FIELDS.includes(k[2])) return { read: true };
      if (k[2] === 'pbrMetallicRoughness' && (k.length < 4 || PBR_FIELDS.includes(k[3])))
        return { read: true };
      if (k[2] === 'extensions' && k[3] === 'KHR_materials_emissive_strength') return { read: true };
      return { read: false, why: 'material field voxgi does not read' };
    case 'textures':
      return roles.textures.has(index) ? { read: true }
        : { read: false, why: 'texture no material reads' };
    case 'images':
      return roles.images.has(index) ? { read: true }
        : { read: false, why: 'image no read texture uses' };
    case 'samplers':
      return roles.samplers.has(index) ? { read: true }
        : { read: false, why: 'sampler no read texture uses' };
    case 'extensions':
      if (k[1] === 'KHR_lights_punctual') return { read: true };
      return { read: false, why: 'extension voxgi does not read' };
    default:
      return { read: false, why: 'top-level property voxgi does not read' };
  }
}

function tolerated(doc, roles, m) {
  for (const t of TOLERATED) {
    const codeOk = t.code instanceof RegExp ? t.code.test(m.code) : t.code === m.code;
    if (codeOk && m.pointer && t.pointer.test(m.pointer) && t.when(doc, m.pointer, roles)) return t.why;
  }
  return null;
}

// The JSON of a .gltf or a .glb's first chunk; null when it cannot be parsed.
function documentOf(bytes) {
  try {
    if (bytes.length >= 20 && bytes.toString('latin1', 0, 4) === 'glTF') {
      const length = bytes.readUInt32LE(12);
      return JSON.parse(bytes.toString('utf8', 20, 20 + length));
    }
    const doc = JSON.parse(bytes.toString('utf8'));
    return doc && typeof doc === 'object' && !Array.isArray(doc) ? doc : null;
  } catch (e) {
    return null;
  }
}

// The validator throws from deep inside its own stack on some inputs (deeply nested
// JSON overflows it): such a throw ends that file's validation as a refusal.
let failCurrent = null;
process.on('uncaughtException', (e) => {
  if (failCurrent) failCurrent(e);
  else throw e;
});

function validate(file, bytes) {
  return new Promise((resolve) => {
    failCurrent = (e) => resolve({ crashed: String(e).split('\n')[0] });
    validator.validateBytes(new Uint8Array(bytes), {
      uri: path.basename(file),
      maxIssues: 0,
      externalResourceFunction: (uri) => new Promise((ok, fail) => {
        fs.readFile(path.join(path.dirname(file), decodeURIComponent(uri)),
          (e, d) => (e ? fail(e.toString()) : ok(new Uint8Array(d))));
      }),
    }).then((report) => resolve({ report }), (e) => resolve({ crashed: String(e).split('\n')[0] }));
  }).finally(() => { failCurrent = null; });
}

// `VOXGI check FILE` for every file, a few at a time (voxgi's start-up, not the
// load, is most of the time), while the validator runs.
function checkAll(voxgi, files) {
  const results = new Array(files.length);
  let next = 0;
  const env = { ...process.env, VOXGI_HUGE_PAGES: '0' };  // no re-exec: a short run
  const worker = () => new Promise((done) => {
    const step = () => {
      if (next >= files.length) return done();
      const i = next++;
      const child = spawn(voxgi, ['check', files[i]], { env, stdio: ['ignore', 'ignore', 'pipe'] });
      let stderr = '';
      child.stderr.on('data', (d) => { stderr += d; });
      child.on('close', (status) => { results[i] = { status, stderr }; step(); });
    };
    step();
  });
  const jobs = Math.max(1, Math.min(os.cpus().length, 8));
  return Promise.all(Array.from({ length: jobs }, worker)).then(() => results);
}

function isSample(file) {
  const dir = path.dirname(path.resolve(file));
  return !dir.endsWith(path.join('tests', 'data', 'malformed'));
}

async function main() {
  const [voxgi, ...files] = process.argv.slice(2);
  if (!voxgi || files.length === 0) {
    console.error('usage: node tools/gltf_validate.js VOXGI FILE...');
    process.exit(2);
  }
  const rows = [];
  let failures = 0;
  const checks = checkAll(voxgi, files);
  const reports = [];
  for (const file of files) {
    const bytes = fs.readFileSync(file);
    reports.push({ bytes, v: await validate(file, bytes) });
  }
  const runs = await checks;
  for (let i = 0; i < files.length; ++i) {
    const file = files[i];
    const { bytes, v } = reports[i];
    const run = runs[i];
    const doc = documentOf(bytes);
    const roles = doc ? readRoles(doc) : null;
    const read = [], unread = [], allowed = [];
    if (v.crashed) read.push({ code: 'VALIDATOR_REFUSED', pointer: '', why: v.crashed });
    for (const m of v.report ? v.report.issues.messages : []) {
      if (m.severity !== 0) continue;
      const part = readPart(doc, roles, m);
      const why = part.read ? tolerated(doc, roles, m) : part.why;
      (part.read ? (why ? allowed : read) : unread).push({ ...m, why });
    }
    const errLines = (run.stderr || '').split('\n').filter((l) => l.startsWith('voxgi: error:'));
    const refusedCleanly = run.status === 1 && errLines.length === 1 &&
      errLines[0].includes(file) && (run.stderr || '').trim().split('\n').length === 1;
    let verdict = 'ok';
    if (read.length > 0) {
      if (!refusedCleanly) verdict = 'FAIL: validator errors in a part voxgi reads, voxgi did not refuse it in one line';
    } else if (isSample(file)) {
      if (run.status !== 0) verdict = 'FAIL: a sample without errors voxgi reads, voxgi did not load it';
    } else if (run.status !== 0) {
      verdict = refusedCleanly ? 'ok (voxgi only)' : 'FAIL: refused, but not in one line';
    }
    if (verdict.startsWith('FAIL')) failures++;
    rows.push({ file: path.relative(process.cwd(), file), read, unread, allowed, status: run.status,
                error: errLines[0] || (run.stderr || '').trim().split('\n')[0] || '', verdict });
  }
  const w = Math.max(...rows.map((r) => r.file.length));
  console.log(`${'file'.padEnd(w)}  read unread allowed  voxgi  verdict`);
  for (const r of rows) {
    const codes = r.read.map((m) => `${m.code}@${m.pointer}`).slice(0, 2).join(' ');
    console.log(`${r.file.padEnd(w)}  ${String(r.read.length).padStart(4)} ${String(r.unread.length).padStart(6)} ` +
                `${String(r.allowed.length).padStart(7)}  ${r.status === 0 ? 'loads ' : 'exit ' + r.status}  ` +
                `${r.verdict}${codes ? '  [' + codes + ']' : ''}`);
    if (r.verdict.startsWith('FAIL')) {
      for (const m of r.read.slice(0, 5)) console.log(`    validator: ${m.code} at ${m.pointer}: ${m.message || m.why}`);
      console.log(`    voxgi: ${r.error || '(loaded)'}`);
    }
    for (const m of r.unread.slice(0, 2)) console.log(`    not read: ${m.code} at ${m.pointer} (${m.why})`);
    for (const m of r.allowed.slice(0, 2)) console.log(`    accepted: ${m.code} at ${m.pointer} (${m.why})`);
  }
  const refused = rows.filter((r) => r.read.length > 0).length;
  console.log(`\n${rows.length} files: ${refused} with validator errors in parts voxgi reads, ` +
              `${rows.filter((r) => r.verdict === 'ok (voxgi only)').length} refused by voxgi only, ` +
              `${failures} failures`);
  process.exit(failures ? 1 : 0);
}

main();
