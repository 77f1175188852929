// validate.mjs - runs the Khronos glTF-Validator on each .gltf/.glb given; exits 1 on any error or warning.
//
// Usage: node validate.mjs [--quiet] FILE...
// Prints, per file, the counts of errors, warnings, infos and hints and every
// message (infos and hints are allowed, but listed). Exit status: 0 when no
// file has an error or a warning, 1 otherwise, 2 on bad usage.
import { readFile } from 'node:fs/promises';
import path from 'node:path';
import validator from 'gltf-validator';

const SEVERITY = ['error', 'warning', 'info', 'hint'];

async function validateFile(file) {
  const bytes = new Uint8Array(await readFile(file));
  const dir = path.dirname(path.resolve(file));
  return validator.validateBytes(bytes, {
    uri: path.basename(file),
    maxIssues: 0, // unlimited
    writeTimestamp: false,
    externalResourceFunction: async (uri) =>
      new Uint8Array(await readFile(path.resolve(dir, decodeURIComponent(uri)))),
  });
}

async function main() {
  const args = process.argv.slice(2);
  const quiet = args[0] === '--quiet';
  const files = quiet ? args.slice(1) : args;
  if (files.length === 0) {
    console.error('usage: node validate.mjs [--quiet] FILE.gltf|FILE.glb ...');
    return 2;
  }
  let bad = 0;
  for (const file of files) {
    let report;
    try {
      report = await validateFile(file);
    } catch (e) {
      console.log(`${file}: FAILED: the validator could not read it: ${e}`);
      bad++;
      continue;
    }
    const { numErrors, numWarnings, numInfos, numHints, messages } = report.issues;
    const info = report.info || {};
    const ok = numErrors === 0 && numWarnings === 0;
    console.log(
      `${file}: ${ok ? 'ok' : 'FAILED'}: ${numErrors} errors, ${numWarnings} warnings, ` +
        `${numInfos} infos, ${numHints} hints` +
        ` (glTF ${info.version ?? '?'}, generator "${info.generator ?? ''}", ` +
        `${info.totalVertexCount ?? 0} vertices, ${info.totalTriangleCount ?? 0} triangles` +
        `${info.extensionsUsed?.length ? ', extensions ' + info.extensionsUsed.join(' ') : ''})`,
    );
    for (const m of messages) {
      if (quiet && m.severity > 1) continue;
      const where = m.pointer ?? (m.offset !== undefined ? `@${m.offset}` : '');
      console.log(`  ${SEVERITY[m.severity] ?? m.severity} ${m.code} ${where}: ${m.message}`);
    }
    if (!ok) bad++;
  }
  return bad ? 1 : 0;
}

process.exitCode = await main();
