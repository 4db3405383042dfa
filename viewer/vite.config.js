// Builds the viewer into dist/ with relative asset paths, so that `cmkit view`
// can serve it from any folder.
import { defineConfig } from 'vite';

export default defineConfig({
  base: './',
  build: { outDir: 'dist', emptyOutDir: true, chunkSizeWarningLimit: 1024 },
});
