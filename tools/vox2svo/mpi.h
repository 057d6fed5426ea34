/* tools/vox2svo/mpi.h - mpirun -n N vox2svo MESH.glb OUT.svo (where built
 * with MPI, VX_HAVE_MPI): the mesh's regions split over the ranks
 * (vx_conv_mesh_share), each rank voxelizing and building the models of its
 * own regions and coding them into their streams of the file, rank 0
 * assembling the scene that one process makes (vx_conv_mesh_assemble, from
 * the models' fields) and writing the file from the ranks' streams. */
#ifndef VX_VOX2SVO_MPI_H
#define VX_VOX2SVO_MPI_H

#include <stdbool.h>
#include <stdint.h>

#include "tools/common/conv.h"

/* Converts this rank's share of the mesh `in`. Rank 0 returns true with the
 * scene (its models have their fields but no arrays: the trees stay coded
 * on their ranks) and what was read (info): the caller writes the file with
 * vox2svo_mpi_write and then calls vox2svo_mpi_end. The other ranks send
 * their coded models to rank 0 as it writes, take part in vox2svo_mpi_end
 * themselves and return false: the caller exits 0.
 * A failure on any rank ends the whole job (MPI_Abort, one line naming the
 * rank), so no rank returns an error. chunking: the models' form
 * (vx_write_desc.svo_chunk_words, svo_chunk_fast; its other fields unused). */
bool vox2svo_mpi(const char* in, const vx_tool_conv* conv, const vx_write_desc* chunking, bool quiet, bool verbose, vx_svo_scene* scene,
                 vx_tool_loaded* info);

/* Rank 0: writes the file (vx_svo_write_file_coded) from every rank's
 * streams, received one at a time in model order. */
vx_result vox2svo_mpi_write(const vx_svo_scene* scene, const char* path, vx_error* err);

/* Rank 0, after writing in seconds_write: gathers every rank's figures,
 * prints them with -v (one line per rank, one summary) and ends MPI. */
void vox2svo_mpi_end(double seconds_write);

#endif
