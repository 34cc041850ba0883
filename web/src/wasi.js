// The few WASI calls depthcull.wasm imports (wasi_snapshot_preview1), for
// browsers and Node alike. The core does no I/O: libc links fd_write,
// fd_seek and fd_close only for its stdio, which nothing in the core writes
// to except a diagnostic before an abort. Node has its own `wasi` module,
// but it prints an experimental-feature warning on every use and does not
// exist in browsers; one shim means the tests under Node exercise the same
// code a browser runs.

const ERRNO_SUCCESS = 0;
const ERRNO_BADF = 8;

/**
 * @param {() => WebAssembly.Memory} memory the instance's memory, once it exists
 * @param {(text: string) => void} log where fd 1 and 2 go
 */
export function wasiImports(memory, log) {
  const decoder = new TextDecoder();
  let pending = '';
  return {
    wasi_snapshot_preview1: {
      fd_write(fd, iovs, iovsLength, writtenPtr) {
        if (fd !== 1 && fd !== 2) return ERRNO_BADF;
        const view = new DataView(memory().buffer);
        let written = 0;
        for (let i = 0; i < iovsLength; ++i) {
          const base = view.getUint32(iovs + i * 8, true);
          const length = view.getUint32(iovs + i * 8 + 4, true);
          pending += decoder.decode(new Uint8Array(memory().buffer, base, length));
          written += length;
        }
        // One log call per line, as a terminal would show it.
        let newline;
        while ((newline = pending.indexOf('\n')) >= 0) {
          log(pending.slice(0, newline));
          pending = pending.slice(newline + 1);
        }
        view.setUint32(writtenPtr, written, true);
        return ERRNO_SUCCESS;
      },
      fd_seek() {
        return ERRNO_BADF;
      },
      fd_close() {
        return ERRNO_SUCCESS;
      },
    },
  };
}
