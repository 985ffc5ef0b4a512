// The page's own modules (web/js), for tests under Node. Browsers load them
// as ES modules; Node reads a .js file outside a package that says
// "type": "module" as CommonJS unless it sniffs the syntax itself (20.19
// and 22 do, Debian 12's Node 18 does not). A copy of the folder under such
// a package.json loads the same files on any Node that runs these tests.
import { cpSync, mkdtempSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, join } from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';

const source = join(dirname(fileURLToPath(import.meta.url)), '..', '..', 'web', 'js');
let copy = null;

export function webModule(name) {
  if (!copy) {
    copy = mkdtempSync(join(tmpdir(), 'causticd-web-'));
    cpSync(source, copy, { recursive: true });
    writeFileSync(join(copy, 'package.json'), '{"type": "module"}\n');
    process.on('exit', () => rmSync(copy, { recursive: true, force: true }));
  }
  return import(pathToFileURL(join(copy, name)).href);
}
